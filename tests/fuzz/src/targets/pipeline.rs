//! The flight pipeline ([`firmware::pipeline::FlightPipeline`], the default build's flight
//! with the `hil` messages) driven by a script ([`crate::script`]) of link bytes, valid
//! frames, IMU samples and control ticks.
//!
//! Invariants, checked after every operation:
//! - no panic;
//! - every tick's throttles are finite and in [0, 1], all 0 whenever the output is not armed,
//!   the output is not armed whenever the state is disarmed, and the status reports the same
//!   throttles;
//! - the link counters are those of a second decoder fed the same bytes (every frame the
//!   decoder saw is counted once: ok, dropped or malformed), every counter is monotone,
//!   `control_ticks` is the number of ticks;
//! - the telemetry fits its buffer, is whole CRC-valid frames (a ground station's decoder
//!   finds nothing malformed and skips no byte);
//! - no reply is lost silently: at the end (telemetry flushed) every command received has its
//!   `COMMAND_ACK` sent, and every state change and refusal its `STATUSTEXT`, or the loss is
//!   counted in `replies_dropped`.

use firmware::config::FlightConfig;
use firmware::link::mavlink::dialects::common::{COMMAND_ACK_DATA, STATUSTEXT_DATA};
use firmware::link::mavlink::MessageData;
use firmware::link::{Decoder, Inbound};
use firmware::pipeline::{Counters, Event, FlightPipeline, ImuSample, MotorOutput};
use firmware::safety::FlightState;

use crate::script::{self, Op, REST_ACCEL_M_S2};

/// Gyro calibration length of the fuzzed flight: the build's 1 000 samples would spend most of
/// every input on it; 50 lets short inputs arm and fly.
pub const CALIBRATION_SAMPLES: u32 = 50;

/// Work cap per input: IMU samples and ticks beyond these end the run (inputs stay fast; a
/// longer flight is a longer input, not a bigger `Rest`).
pub const MAX_IMU_SAMPLES: u32 = 20_000;
/// See [`MAX_IMU_SAMPLES`].
pub const MAX_TICKS: u32 = 2_000;

/// The fuzzed flight: the default build's ([`FlightConfig::built`]) with a short gyro
/// calibration.
pub fn config() -> FlightConfig {
    FlightConfig {
        gyro_calibration_samples: CALIBRATION_SAMPLES,
        ..FlightConfig::built()
    }
}

/// What the ground station saw of the telemetry.
#[derive(Default)]
struct GroundStation {
    decoder: Option<Decoder>,
    acks: u64,
    texts: u64,
}

impl GroundStation {
    /// Takes one telemetry call's bytes: whole, CRC-valid MAVLink 2 frames.
    fn take(&mut self, bytes: &[u8]) {
        let decoder = self.decoder.get_or_insert_with(|| Decoder::new(255));
        decoder.push(bytes, |_| {});
        let c = decoder.counters();
        assert!(
            c.frames_malformed == 0 && c.bytes_discarded == 0,
            "telemetry is not whole valid frames: {c:?}"
        );
        let mut i = 0;
        while i < bytes.len() {
            assert!(
                bytes[i] == 0xFD && i + 12 <= bytes.len(),
                "telemetry frame {i} is cut"
            );
            let len = usize::from(bytes[i + 1]);
            let id = u32::from_le_bytes([bytes[i + 7], bytes[i + 8], bytes[i + 9], 0]);
            match id {
                COMMAND_ACK_DATA::ID => self.acks += 1,
                STATUSTEXT_DATA::ID => self.texts += 1,
                _ => {}
            }
            i += 12 + len;
        }
        assert_eq!(i, bytes.len(), "telemetry ends inside a frame");
    }
}

fn monotone(a: &Counters, b: &Counters) -> bool {
    let (la, lb) = (&a.link, &b.link);
    lb.frames_ok >= la.frames_ok
        && lb.frames_dropped >= la.frames_dropped
        && lb.frames_malformed >= la.frames_malformed
        && lb.bytes_discarded >= la.bytes_discarded
        && b.non_finite >= a.non_finite
        && b.refused_commands >= a.refused_commands
        && b.events_dropped >= a.events_dropped
        && b.mixer_saturations >= a.mixer_saturations
        && b.control_ticks >= a.control_ticks
        && b.imu_samples >= a.imu_samples
        && b.poses_used >= a.poses_used
        && b.telemetry_dropped >= a.telemetry_dropped
        && b.replies_dropped >= a.replies_dropped
}

fn check_output(out: &MotorOutput, p: &FlightPipeline) {
    for u in out.throttle {
        assert!(
            u.is_finite() && (0.0..=1.0).contains(&u),
            "throttle {u} out of [0, 1]: {out:?}"
        );
    }
    if !out.armed {
        assert_eq!(out.throttle, [0.0; 4], "throttle while not armed");
    }
    let st = p.status();
    if st.state == FlightState::Disarmed {
        assert!(!out.armed, "armed output in the disarmed state");
    }
    assert_eq!(
        st.throttle.map(f32::to_bits),
        out.throttle.map(f32::to_bits),
        "the status reports other throttles than the tick's"
    );
}

/// The pipeline under test with its independent observers.
struct Harness {
    p: FlightPipeline,
    shadow: Decoder,
    gcs: GroundStation,
    now: u64,
    sequence: u8,
    ticks: u32,
    imu_calls: u32,
    commands: u64,
    texts_due: u64,
    events_lost: bool,
    telemetry: Vec<u8>,
}

impl Harness {
    fn link(&mut self, bytes: &[u8]) {
        self.p.on_link_bytes(bytes, self.now);
        let mut commands = 0;
        self.shadow.push(bytes, |m| {
            if matches!(m, Inbound::Command { .. } | Inbound::CommandFault { .. }) {
                commands += 1;
            }
        });
        self.commands += commands;
    }

    fn imu(&mut self, gyro: [f32; 3], accel: [f32; 3], dt: u64) {
        self.now += dt;
        self.imu_calls += 1;
        self.p.on_imu(&ImuSample {
            gyro_rad_s: gyro,
            accel_m_s2: accel,
            time_us: self.now,
        });
    }

    fn tick(&mut self, dt: u64, room: usize) {
        self.now += dt;
        self.ticks += 1;
        let out = self.p.control_tick(self.now);
        check_output(&out, &self.p);
        self.flush(room);
    }

    /// One telemetry call into a buffer of `room` bytes; the number of bytes written.
    fn flush(&mut self, room: usize) -> usize {
        let n = self.p.telemetry(self.now, &mut self.telemetry[..room]);
        assert!(n <= room, "telemetry wrote {n} bytes into {room}");
        self.gcs.take(&self.telemetry[..n]);
        n
    }

    fn apply(&mut self, op: &Op) {
        match op {
            Op::Bytes(b) => self.link(b),
            Op::Frame { spec, chunk } => {
                let f = script::frame_bytes(spec, self.now, self.sequence);
                self.sequence = self.sequence.wrapping_add(1);
                for c in f.chunks(usize::from(*chunk).max(1)) {
                    self.link(c);
                }
            }
            Op::Imu { gyro, accel, dt } => self.imu(*gyro, *accel, u64::from(*dt)),
            Op::ImuQuantised { gyro, accel } => self.imu(
                gyro.map(|x| f32::from(x) * 1e-3),
                accel.map(|x| f32::from(x) * 1e-2),
                1000,
            ),
            Op::Rest(n) => {
                for _ in 0..*n {
                    self.imu([0.0; 3], [0.0, 0.0, REST_ACCEL_M_S2], 1000);
                }
            }
            Op::Tick { dt, room } => self.tick(u64::from(*dt), usize::from(*room)),
        }
        while let Some(e) = self.p.take_events() {
            if matches!(e, Event::StateChanged { .. } | Event::CommandRefused { .. }) {
                self.texts_due += 1;
            }
        }
    }
}

/// Runs the target on one input; panics on a broken invariant.
pub fn run(data: &[u8]) {
    let cfg = config();
    let Ok(p) = FlightPipeline::new(&cfg) else {
        panic!("the default build's flight does not boot");
    };
    let mut h = Harness {
        p,
        shadow: Decoder::new(cfg.system_id),
        gcs: GroundStation::default(),
        now: 0,
        sequence: 0,
        ticks: 0,
        imu_calls: 0,
        commands: 0,
        texts_due: 0,
        events_lost: false,
        telemetry: vec![0; 2048],
    };
    let mut before = h.p.status().counters;
    for op in script::parse(data) {
        if h.imu_calls > MAX_IMU_SAMPLES || h.ticks > MAX_TICKS {
            break;
        }
        h.apply(&op);
        let c = h.p.status().counters;
        assert!(
            monotone(&before, &c),
            "a counter went down: {before:?} -> {c:?}"
        );
        assert_eq!(
            c.link,
            h.shadow.counters(),
            "the pipeline's link counters differ from a decoder fed the same bytes"
        );
        assert_eq!(
            c.control_ticks, h.ticks,
            "control_ticks is not the number of ticks"
        );
        assert!(c.imu_samples >= h.imu_calls, "IMU samples not counted");
        h.events_lost |= c.events_dropped > 0;
        before = c;
    }
    // Drain what is pending (acks and texts first; each call sends at least one frame while
    // any is pending, and at most 16 are).
    for _ in 0..40 {
        if h.flush(2048) == 0 {
            break;
        }
    }
    let c = h.p.status().counters;
    let replies_dropped = u64::from(c.replies_dropped);
    assert!(
        h.gcs.acks <= h.commands,
        "{} acks for {} commands",
        h.gcs.acks,
        h.commands
    );
    if !h.events_lost {
        assert_eq!(
            h.commands + h.texts_due,
            h.gcs.acks + h.gcs.texts + replies_dropped,
            "a reply was lost silently: {} commands and {} state changes or refusals, \
             {} acks and {} texts sent, {} counted as dropped",
            h.commands,
            h.texts_due,
            h.gcs.acks,
            h.gcs.texts,
            replies_dropped
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::script::{encode, FrameSpec};

    /// Nine arm commands during the gyro calibration, no telemetry in between: nine refusals,
    /// each an ack and a text, one more of each than their queues hold.
    #[test]
    fn nine_refused_commands_lose_no_reply_silently() {
        let arm = Op::Frame {
            spec: FrameSpec::Command {
                command: 0,
                target: 1,
                params: [1.0, 0.0, 0.0],
            },
            chunk: 64,
        };
        run(&encode(&vec![arm; 9]));
    }
}
