//! The flight pipeline ([`firmware::pipeline::FlightPipeline`], the default build's flight
//! with the `hil` messages, on a trusted link: [`config`]) driven by a script ([`crate::script`]) of link bytes, valid
//! frames, IMU samples and control ticks.
//!
//! Invariants, checked after every operation:
//! - no panic;
//! - every tick's throttles are finite and in [0, 1], all 0 whenever the output is not armed,
//!   the output is not armed whenever the state is disarmed, and the status reports the same
//!   throttles;
//! - the link counters are those of a second decoder fed the same bytes (every frame the
//!   decoder saw is counted once: ok, dropped or malformed; a `SETUP_SIGNING` the pipeline
//!   accepts installs the same key in it at the same byte), every counter is monotone,
//!   `control_ticks` is the number of ticks;
//! - the telemetry fits its buffer, is whole CRC-valid frames (a ground station's decoder
//!   finds nothing malformed and skips no byte), signed exactly when a key is installed;
//! - no reply is lost silently: at the end (telemetry flushed) every command received has its
//!   `COMMAND_ACK` sent, and every state change and refusal its `STATUSTEXT`, or the loss is
//!   counted in `replies_dropped`; exactly so (no other ack or text) when no mission-protocol
//!   message arrived, at least so otherwise (the mission protocol adds `STATUSTEXT`s of its own,
//!   and the losses of its replies to the same counter).

use firmware::config::FlightConfig;
use firmware::link::mavlink::dialects::common::{COMMAND_ACK_DATA, STATUSTEXT_DATA};
use firmware::link::mavlink::MessageData;
use firmware::link::{Decoder, Inbound, LinkTrust, SigningConfig};
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
/// calibration, on a trusted (wired) link: there an unsigned `SETUP_SIGNING` in an input
/// installs or replaces a key, so the keyed rules are fuzzed too. On the default, untrusted
/// link no input could ever install one (it would need the key it installs).
pub fn config() -> FlightConfig {
    FlightConfig {
        gyro_calibration_samples: CALIBRATION_SAMPLES,
        link_trust: LinkTrust::Trusted,
        ..FlightConfig::built()
    }
}

/// What the ground station saw of the telemetry.
#[derive(Default)]
struct GroundStation {
    decoder: Option<Decoder>,
    acks: u64,
    texts: u64,
    /// Frames received per message id.
    frames: std::collections::BTreeMap<u32, u64>,
    /// A signing key is installed: everything the vehicle sends must be signed from then on.
    keyed: bool,
}

impl GroundStation {
    /// Takes one telemetry call's bytes: whole, CRC-valid MAVLink 2 frames, signed exactly when
    /// the link has a key.
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
            let signed = bytes[i + 2] & 0x01 != 0;
            assert_eq!(
                signed, self.keyed,
                "telemetry frame {i}: signed {signed}, the link keyed {}",
                self.keyed
            );
            let id = u32::from_le_bytes([bytes[i + 7], bytes[i + 8], bytes[i + 9], 0]);
            *self.frames.entry(id).or_default() += 1;
            match id {
                COMMAND_ACK_DATA::ID => self.acks += 1,
                STATUSTEXT_DATA::ID => self.texts += 1,
                _ => {}
            }
            i += 12 + len + if signed { firmware::link::SIGNATURE } else { 0 };
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
    /// Mission-protocol messages received (`Inbound::Mission`).
    missions: u64,
    texts_due: u64,
    events_lost: bool,
    /// A `SETUP_SIGNING`'s verdict was lost with its event: the shadow decoder cannot follow
    /// the pipeline's key from there, and the link counters are no longer compared.
    shadow_blind: bool,
    /// The flight's signing rule for unsigned sensors, for the keys the shadow takes.
    accept_unsigned_sensors: bool,
    telemetry: Vec<u8>,
    /// The counters after the last operation.
    counters: Counters,
}

impl Harness {
    /// The fuzzed flight, booted, with its observers.
    fn new(cfg: &FlightConfig) -> Self {
        let Ok(p) = FlightPipeline::new(cfg) else {
            panic!("the default build's flight does not boot");
        };
        let counters = p.status().counters;
        Self {
            p,
            // The same link trust as the pipeline's decoder: it decides who may set the key.
            shadow: Decoder::new(cfg.system_id).with_trust(cfg.link_trust),
            gcs: GroundStation::default(),
            now: 0,
            sequence: 0,
            ticks: 0,
            imu_calls: 0,
            commands: 0,
            missions: 0,
            texts_due: 0,
            events_lost: false,
            shadow_blind: false,
            accept_unsigned_sensors: cfg.accept_unsigned_sensors,
            telemetry: vec![0; 2048],
            counters,
        }
    }

    fn link(&mut self, bytes: &[u8]) {
        let dropped_before = self.p.status().counters.events_dropped;
        self.p.on_link_bytes(bytes, self.now);
        // The pipeline's verdicts on the chunk's `SETUP_SIGNING`s, in order: an accepted one
        // installs the key in its decoder at once, and every later frame of the chunk is judged
        // with it. The shadow takes the verdict (the command policy: disarmed) and installs the
        // key at the same byte, so its counters stay an independent check of the decoder.
        let mut verdicts = std::collections::VecDeque::new();
        for e in self.take_events() {
            match e {
                Event::CommandAccepted {
                    command: "setup_signing",
                } => verdicts.push_back(true),
                Event::CommandRefused {
                    command: "setup_signing",
                    ..
                } => verdicts.push_back(false),
                _ => {}
            }
        }
        let verdicts_whole = self.p.status().counters.events_dropped == dropped_before;
        let mut commands = 0;
        let mut missions = 0;
        // `Decoder::push`'s loop, with the message handled before the next byte goes in.
        let mut rest = bytes;
        while let (used, Some(m)) = self.shadow.feed(rest) {
            rest = &rest[used..];
            match m {
                Inbound::Command { .. } | Inbound::CommandFault { .. } => commands += 1,
                Inbound::Mission { .. } => missions += 1,
                Inbound::SetupSigning {
                    key,
                    initial_timestamp,
                    ..
                } => match verdicts.pop_front() {
                    Some(true) => {
                        let config = SigningConfig {
                            key,
                            link_id: 0,
                            accept_unsigned_sensors: self.accept_unsigned_sensors,
                        };
                        assert!(
                            self.shadow.install_signing_key(config, initial_timestamp),
                            "the pipeline installed a signing key its decoder's rules refuse"
                        );
                        self.gcs.keyed = true;
                    }
                    Some(false) => {}
                    // Its event was dropped from a full queue: the verdict is unknown.
                    None => {
                        assert!(!verdicts_whole, "a SETUP_SIGNING without a verdict");
                        self.shadow_blind = true;
                    }
                },
                _ => {}
            }
        }
        self.commands += commands;
        self.missions += missions;
    }

    /// The pipeline's pending events; a state change or a refusal is a `STATUSTEXT` due.
    fn take_events(&mut self) -> Vec<Event> {
        let mut events = Vec::new();
        while let Some(e) = self.p.take_events() {
            if matches!(e, Event::StateChanged { .. } | Event::CommandRefused { .. }) {
                self.texts_due += 1;
            }
            events.push(e);
        }
        events
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
        self.take_events();
    }

    /// Applies `op` and checks the invariants that hold after every operation; `false` (and
    /// nothing applied) once the input's work cap is reached.
    fn step(&mut self, op: &Op) -> bool {
        if self.imu_calls > MAX_IMU_SAMPLES || self.ticks > MAX_TICKS {
            return false;
        }
        self.apply(op);
        let before = self.counters;
        let c = self.p.status().counters;
        assert!(
            monotone(&before, &c),
            "a counter went down: {before:?} -> {c:?}"
        );
        if !self.shadow_blind {
            assert_eq!(
                c.link,
                self.shadow.counters(),
                "the pipeline's link counters differ from a decoder fed the same bytes"
            );
        }
        assert_eq!(
            c.control_ticks, self.ticks,
            "control_ticks is not the number of ticks"
        );
        assert!(c.imu_samples >= self.imu_calls, "IMU samples not counted");
        self.events_lost |= c.events_dropped > 0;
        self.counters = c;
        true
    }

    /// Flushes the telemetry and checks the reply accounting.
    fn finish(mut self) {
        // Drain what is pending (acks and texts first; each call sends at least one frame while
        // any is pending, and at most 16 command replies, 8 mission replies and 4 mission texts
        // are).
        for _ in 0..40 {
            if self.flush(2048) == 0 {
                break;
            }
        }
        let h = self;
        let c = h.p.status().counters;
        let replies_dropped = u64::from(c.replies_dropped);
        assert!(
            h.gcs.acks <= h.commands,
            "{} acks for {} commands",
            h.gcs.acks,
            h.commands
        );
        if !h.events_lost {
            let due = h.commands + h.texts_due;
            let accounted = h.gcs.acks + h.gcs.texts + replies_dropped;
            let detail = format!(
                "{} commands and {} state changes or refusals, {} acks and {} texts sent, {} \
                 counted as dropped, {} mission messages",
                h.commands, h.texts_due, h.gcs.acks, h.gcs.texts, replies_dropped, h.missions
            );
            // The mission protocol's own texts (refusals with numbers, a land refused at a
            // mission's end) and its dropped replies add to the right side: only the loss of a
            // command's reply is checked then.
            if h.missions == 0 {
                assert_eq!(due, accounted, "a reply was lost silently: {detail}");
            } else {
                assert!(due <= accounted, "a reply was lost silently: {detail}");
            }
        }
    }
}

/// Runs the target on one input; panics on a broken invariant.
pub fn run(data: &[u8]) {
    run_with(&config(), data);
}

/// [`run`] on the flight `cfg` (the fuzzed flight on the untrusted link too, for the tests).
fn run_with(cfg: &FlightConfig, data: &[u8]) {
    let mut h = Harness::new(cfg);
    for op in script::parse(data) {
        if !h.step(&op) {
            break;
        }
    }
    h.finish();
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::script::{encode, FrameSpec, MissionSpec};
    use firmware::link::mavlink::dialects::common::{
        MISSION_ACK_DATA, MISSION_CURRENT_DATA, MISSION_ITEM_REACHED_DATA, MISSION_REQUEST_INT_DATA,
    };
    use firmware::pipeline::Mode;

    fn frame(spec: FrameSpec) -> Op {
        Op::Frame { spec, chunk: 64 }
    }

    fn mission(message: MissionSpec) -> Op {
        frame(FrameSpec::Mission { target: 1, message })
    }

    /// `n` control periods (10 ms) of a vehicle at rest whose poses hold it 1 m up (NED z = -1),
    /// each ending with a tick and a telemetry call.
    fn at_rest_1m_up(n: usize) -> Vec<Op> {
        let period = [
            Op::Rest(10),
            frame(FrameSpec::Mocap {
                position: [0.0, 0.0, -1.0],
                q: [1.0, 0.0, 0.0, 0.0],
            }),
            Op::Tick { dt: 0, room: 2047 },
        ];
        period.iter().cycle().take(3 * n).cloned().collect()
    }

    /// `MAV_CMD` number `command` of [`script::COMMANDS`] for the vehicle with param1 `p1`.
    fn command(command: u8, p1: f32) -> Op {
        frame(FrameSpec::Command {
            command,
            target: 1,
            params: [p1, 0.0, 0.0],
        })
    }

    /// A mission item in `MAV_FRAME_LOCAL_NED` (frame number 1) at NED `z` \[m\] above the
    /// origin, with hold param1.
    fn item(seq: u16, command: u8, z: f32, hold: f32) -> Op {
        mission(MissionSpec::ItemInt {
            seq,
            command,
            frame: 1,
            xy: [0, 0],
            z,
            params: [hold, 0.0, 0.0, 0.0],
        })
    }

    /// Sanity of the mission kind: calibrated and armed on poses 1 m up, a mission of two items
    /// (a takeoff to that height, a waypoint there) is uploaded (`MISSION_COUNT` 2, then each
    /// item), accepted, started with `MAV_CMD_MISSION_START`, and flown to its end (each item
    /// reached, then a hover), every invariant checked on the way.
    #[test]
    fn an_uploaded_mission_is_accepted_started_and_flown() {
        let mut ops = at_rest_1m_up(60);
        ops.push(command(0, 1.0)); // arm
        ops.extend(at_rest_1m_up(1));
        ops.push(mission(MissionSpec::Count { count: 2 }));
        ops.push(item(0, 1, -1.0, 0.0)); // takeoff
        ops.push(item(1, 0, -1.0, 0.2)); // waypoint
        ops.extend(at_rest_1m_up(1));
        ops.push(command(4, 0.0)); // mission start
        ops.extend(at_rest_1m_up(1));
        let started = ops.len();
        ops.extend(at_rest_1m_up(100));

        let mut h = Harness::new(&config());
        for (i, op) in ops.iter().enumerate() {
            assert!(h.step(op), "the work cap at operation {i}");
            if i + 1 == started {
                assert_eq!(
                    h.p.status().mode,
                    Mode::Mission,
                    "the mission did not start"
                );
            }
        }
        assert_eq!(
            h.p.status().mode,
            Mode::Hover,
            "the mission did not end in a hover"
        );
        let seen = |id| h.gcs.frames.get(&id).copied().unwrap_or(0);
        assert_eq!(
            seen(MISSION_REQUEST_INT_DATA::ID),
            2,
            "one request per item"
        );
        assert_eq!(seen(MISSION_ACK_DATA::ID), 1, "the upload's ack");
        assert_eq!(seen(MISSION_ITEM_REACHED_DATA::ID), 2, "each item reached");
        assert!(seen(MISSION_CURRENT_DATA::ID) >= 1);
        assert_eq!(h.missions, 3);
        h.finish();
        // The same script as the target's input.
        run(&encode(&ops));
    }

    /// Mission refusals send `STATUSTEXT`s of their own, with no command or event behind them
    /// (here `MISSION_COUNT` beyond the capacity and a land item that is not last), and every
    /// other mission message goes through on the ground: the reply accounting takes them (its
    /// exact form, for inputs without mission messages, fails on this one).
    #[test]
    fn mission_refusals_with_texts_keep_the_reply_accounting() {
        let mut ops = at_rest_1m_up(60);
        ops.push(mission(MissionSpec::Count { count: 40 }));
        ops.push(mission(MissionSpec::Count { count: 2 }));
        ops.push(item(0, 2, 0.0, 0.0)); // land first
        ops.push(item(1, 0, -1.0, 0.0));
        ops.push(mission(MissionSpec::RequestList));
        ops.push(mission(MissionSpec::SetCurrent { seq: 5 }));
        ops.push(mission(MissionSpec::RequestInt { seq: 0 }));
        ops.push(mission(MissionSpec::ClearAll));
        ops.push(mission(MissionSpec::Ack { result: 3 }));
        ops.extend(at_rest_1m_up(2));
        let mut h = Harness::new(&config());
        for op in &ops {
            assert!(h.step(op));
        }
        h.finish();
        run(&encode(&ops));
    }

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

    /// `SETUP_SIGNING` for the vehicle, sent unsigned by the ground station (255, 190).
    fn setup_signing_frame(key_byte: u8) -> Vec<u8> {
        use firmware::link::mavlink::dialects::common::{MavMessage, SETUP_SIGNING_DATA};
        let m = MavMessage::SETUP_SIGNING(SETUP_SIGNING_DATA {
            initial_timestamp: 1,
            target_system: 1,
            target_component: 1,
            secret_key: [key_byte; 32],
        });
        let mut buf = [0u8; firmware::link::MAX_FRAME];
        let n = firmware::link::encode(&m, 255, 190, 0, &mut buf);
        buf[..n].to_vec()
    }

    /// Found by the long run (3.7 million inputs): an accepted `SETUP_SIGNING` keys the
    /// pipeline's decoder, which then refuses the unsigned frames after it, in the same chunk
    /// too; the harness's second decoder must take the key at the same byte (it did not, and
    /// counted those frames as accepted). On the fuzzed flight's trusted (wired) link,
    /// disarmed: accepted, then a command refused unsigned; an all-zero key: refused, and the
    /// command after it accepted as before. On the default, untrusted link the unsigned
    /// `SETUP_SIGNING` is refused and both decoders stay without a key.
    #[test]
    fn the_second_decoder_follows_a_key_installed_mid_chunk() {
        let radio = FlightConfig {
            link_trust: LinkTrust::Untrusted,
            ..config()
        };
        let command = script::frame_bytes(
            &FrameSpec::Command {
                command: 0,
                target: 1,
                params: [1.0, 0.0, 0.0],
            },
            0,
            1,
        );
        for key_byte in [7u8, 0] {
            let mut chunk = setup_signing_frame(key_byte);
            chunk.extend_from_slice(&command);
            assert!(chunk.len() <= 255, "one Op::Bytes holds at most 255 bytes");
            for cfg in [&config(), &radio] {
                run_with(
                    cfg,
                    &encode(&[Op::Bytes(chunk.clone()), Op::Bytes(command.clone())]),
                );
            }
        }
    }
}
