//! Tests of the PIL link against a fake firmware: the in-process pipeline behind the PIL
//! protocol (what the board layer does on QEMU), over an in-memory transport.

use std::collections::VecDeque;
use std::time::Duration;

use anyhow::Result;
use firmware::frames;
use firmware::link::mavlink::dialects::common::{
    HilActuatorControlsFlags, MavMessage, MavModeFlag, HIL_ACTUATOR_CONTROLS_DATA,
    POSITION_TARGET_LOCAL_NED_DATA,
};
use firmware::link::{self};
use firmware::pipeline::{FlightPipeline, ImuSample};
use nalgebra::Vector3;

use super::chunking::SendChunking;
use super::firmware_link::FirmwareLink;
use super::frames::FrameReader;
use super::transport::Transport;
use crate::harness::qemu::Received;
use crate::harness::sil::{self, scenarios};

/// How the fake misbehaves.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Fault {
    None,
    /// Exits (output closes) at this tick time \[µs\].
    Crash(u64),
    /// Stops answering at this tick time \[µs\].
    Hang(u64),
    /// Answers this tick time \[µs\] with a time 1 µs off.
    WrongTime(u64),
}

/// The flight pipeline behind the PIL protocol, answering synchronously.
struct FakeFirmware {
    pipeline: FlightPipeline,
    reader: FrameReader,
    out: VecDeque<Vec<u8>>,
    hil_time: Option<u64>,
    deadline: u64,
    sequence: u8,
    telemetry: Vec<u8>,
    fault: Fault,
    dead: bool,
    /// Every byte received, in order.
    sent: Vec<u8>,
    /// `controls[k]` carries rotor `slots[k]`'s throttle (the firmware's motor order).
    slots: [usize; 4],
}

impl FakeFirmware {
    fn new(pipeline: FlightPipeline, fault: Fault) -> Self {
        Self {
            pipeline,
            reader: FrameReader::new(),
            out: VecDeque::new(),
            hil_time: None,
            deadline: 0,
            sequence: 0,
            telemetry: vec![0; 1024],
            fault,
            dead: false,
            sent: Vec::new(),
            slots: [0, 1, 2, 3],
        }
    }

    fn emit(&mut self, m: &MavMessage) {
        let mut buf = [0u8; link::MAX_FRAME];
        let n = link::encode(m, 1, 1, self.sequence, &mut buf);
        self.sequence = self.sequence.wrapping_add(1);
        self.out.push_back(buf[..n].to_vec());
    }

    fn tick(&mut self, t: u64) {
        match self.fault {
            Fault::Crash(at) | Fault::Hang(at) if t >= at => {
                self.dead = true;
                return;
            }
            _ => {}
        }
        let out = self.pipeline.control_tick(t);
        let mut controls = [0.0f32; 16];
        for (c, &rotor) in controls.iter_mut().zip(&self.slots) {
            *c = out.throttle[rotor];
        }
        let stamp = if self.fault == Fault::WrongTime(t) {
            t + 1
        } else {
            t
        };
        self.emit(&MavMessage::HIL_ACTUATOR_CONTROLS(
            HIL_ACTUATOR_CONTROLS_DATA {
                time_usec: stamp,
                controls,
                mode: if out.armed {
                    MavModeFlag::MAV_MODE_FLAG_SAFETY_ARMED
                } else {
                    MavModeFlag::empty()
                },
                // As the firmware: the host must wait for this frame before it steps.
                flags: HilActuatorControlsFlags::HIL_ACTUATOR_CONTROLS_FLAGS_LOCKSTEP,
            },
        ));
        let [x, y, z] =
            frames::flip_to_array(&Vector3::from(self.pipeline.status().reference_position));
        self.emit(&MavMessage::POSITION_TARGET_LOCAL_NED(
            POSITION_TARGET_LOCAL_NED_DATA {
                time_boot_ms: (t / 1000) as u32,
                x,
                y,
                z,
                ..Default::default()
            },
        ));
        // The telemetry after the tick's frames: the host reads it with the next tick.
        let n = self.pipeline.telemetry(t, &mut self.telemetry);
        self.out.push_back(self.telemetry[..n].to_vec());
        while self.pipeline.take_events().is_some() {}
    }
}

impl Transport for FakeFirmware {
    fn send(&mut self, bytes: &[u8]) -> Result<()> {
        self.sent.extend_from_slice(bytes);
        self.reader.push(bytes);
        while let Some((h, m)) = self.reader.next_message() {
            if let MavMessage::HIL_SENSOR(s) = &m {
                let [ax, ay, az] = frames::flip_to_array(&Vector3::new(s.xacc, s.yacc, s.zacc));
                let [gx, gy, gz] = frames::flip_to_array(&Vector3::new(s.xgyro, s.ygyro, s.zgyro));
                self.pipeline.on_imu(&ImuSample {
                    gyro_rad_s: [gx, gy, gz],
                    accel_m_s2: [ax, ay, az],
                    time_us: s.time_usec,
                });
                self.hil_time = Some(s.time_usec);
                if s.time_usec >= self.deadline && !self.dead {
                    self.tick(s.time_usec);
                    self.deadline = s.time_usec + 10_000;
                }
            } else {
                let mut buf = [0u8; link::MAX_FRAME];
                let n = link::encode(&m, h.system_id as u8, h.component_id, h.sequence, &mut buf);
                self.pipeline
                    .on_link_bytes(&buf[..n], self.hil_time.unwrap_or(0));
            }
        }
        Ok(())
    }

    fn receive(&mut self, _timeout: Duration) -> Received {
        match self.out.pop_front() {
            Some(b) => Received::Bytes(b),
            None if matches!(self.fault, Fault::Crash(_)) && self.dead => Received::Closed,
            None => Received::Timeout,
        }
    }

    fn post_mortem(&mut self) -> String {
        "fake firmware".into()
    }
}

/// The telemetry the host takes in (raw frames) and the bytes the fake received, flying
/// `setup` with the host's writes cut as `chunking` says.
fn fly_recording(setup: &sil::SilSetup, chunking: SendChunking) -> (Vec<u8>, Vec<u8>) {
    let pipeline = FlightPipeline::new(&setup.flight).unwrap();
    let boot = pipeline.boot_report();
    let b = pipeline.mixer().effectiveness().cast::<f64>();
    let fake = FakeFirmware::new(pipeline, Fault::None);
    let mut link = FirmwareLink::new(fake, &setup.flight, b, Duration::from_millis(1))
        .with_send_chunking(chunking)
        .recording();
    sil::fly(setup, &boot, &b, &mut link, |_| {}).unwrap();
    let received = link.received().unwrap().to_vec();
    (received, link.into_transport().sent)
}

/// Given the paper scenario (0.5 s: the random writes' pauses are wall-clock time), when the
/// host cuts its writes whole, per byte or at random, then the firmware receives the same bytes
/// and the host records the same telemetry, which holds every tick's answer.
#[test]
fn send_chunking_changes_the_writes_only() {
    let mut setup = scenarios::paper(1);
    setup.hold_s = 0.2;
    setup.duration_s = 0.3;
    let (telemetry, sent) = fly_recording(&setup, SendChunking::Whole);
    // A tick every 10 ms, both ends included.
    let ticks = (100.0 * (setup.hold_s + setup.duration_s)).round() as usize + 1;
    let mut r = FrameReader::new();
    r.push(&telemetry);
    let actuators = std::iter::from_fn(|| r.next_message())
        .filter(|(_, m)| matches!(m, MavMessage::HIL_ACTUATOR_CONTROLS(_)))
        .count();
    assert_eq!(actuators, ticks);
    assert_eq!(r.counters().malformed, 0);
    for chunking in [SendChunking::Bytes, SendChunking::Random { seed: 3 }] {
        let (t, s) = fly_recording(&setup, chunking);
        assert!(s == sent, "{chunking}: other bytes sent");
        assert!(t == telemetry, "{chunking}: other telemetry");
    }
}

fn fly(mut setup: sil::SilSetup, fault: Fault) -> (Result<sil::SilSummary>, Vec<sil::SilRecord>) {
    setup.duration_s = setup.duration_s.min(30.0);
    let pipeline = FlightPipeline::new(&setup.flight).unwrap();
    let boot = pipeline.boot_report();
    let b = pipeline.mixer().effectiveness().cast::<f64>();
    let fake = FakeFirmware::new(FlightPipeline::new(&setup.flight).unwrap(), fault);
    let mut link = FirmwareLink::new(fake, &setup.flight, b, Duration::from_millis(1));
    let mut records = Vec::new();
    let s = sil::fly(&setup, &boot, &b, &mut link, |r| records.push(r.clone()));
    (s, records)
}

/// Given a firmware that sends its motor outputs in Betaflight's order, when the host is told
/// so, then the flight is the one in the vehicle file's order, record for record; told
/// nothing, the host applies the throttles to the wrong rotors and the flight differs.
#[test]
fn the_host_puts_the_motor_order_back() {
    use firmware::motor_order::MotorOrder;
    let mut setup = scenarios::helix(1);
    setup.duration_s = 2.0;
    let run = |firmware_order: MotorOrder, host_order: MotorOrder| {
        let pipeline = FlightPipeline::new(&setup.flight).unwrap();
        let boot = pipeline.boot_report();
        let b = pipeline.mixer().effectiveness().cast::<f64>();
        let mut fake = FakeFirmware::new(FlightPipeline::new(&setup.flight).unwrap(), Fault::None);
        fake.slots = firmware_order.slots(&setup.flight.rotors.rotors).unwrap();
        let mut link = FirmwareLink::new(fake, &setup.flight, b, Duration::from_millis(1))
            .with_motor_order(host_order)
            .unwrap();
        let mut records = Vec::new();
        sil::fly(&setup, &boot, &b, &mut link, |r| records.push(r.clone())).unwrap();
        records
    };
    let mixer = run(MotorOrder::Mixer, MotorOrder::Mixer);
    let betaflight = run(MotorOrder::Betaflight, MotorOrder::Betaflight);
    assert_eq!(format!("{mixer:?}"), format!("{betaflight:?}"));
    let wrong = run(MotorOrder::Betaflight, MotorOrder::Mixer);
    assert_ne!(format!("{mixer:?}"), format!("{wrong:?}"));
}

/// The `helix` scenario (the built vehicle's demo mission from an upright start 4.1 m away)
/// through the PIL protocol (FRD sensor frames, MAVLink both ways, the reconstruction of state,
/// mode, reference and wrench from telemetry) flies as in SIL (host-sim/tests/sil_paper.rs:
/// the same settling bound): certified at boot, converges, thrust inside the certificate's
/// interval.
#[test]
fn helix_flight_through_the_pil_protocol_converges() {
    let setup = scenarios::helix(1);
    let bounds = setup.a_priori_bounds().unwrap();
    let g = setup.flight.gains.position;
    let (s, records) = fly(setup, Fault::None);
    let s = s.unwrap();
    assert!(s.certificate_holds && s.fit_margin >= s.required_fit_margin);
    assert_eq!(records.len(), 3151); // `fly` stops at 30 s
    assert_eq!(s.final_state, "armed", "{:#?}", s.events);
    assert!(s
        .events
        .iter()
        .any(|(_, e)| e.contains("disarmed -> armed")));
    assert!(s.events.iter().any(|(_, e)| e == "mode helix"));
    let expected =
        2.0 * (4.1 / f64::from(g.saturation)).sqrt() + (4.1f64 / 0.05).ln() / f64::from(g.kf);
    let settled = s.below_5cm_from_s.expect("never below 5 cm");
    assert!(settled < expected, "{settled} vs {expected}");
    assert!(
        s.final_position_error_m < 0.05,
        "{}",
        s.final_position_error_m
    );
    assert_eq!(s.throttle_violations, 0);
    assert_eq!(s.spun_while_disarmed, 0);
    assert_eq!(s.telemetry_frames[1], 0);
    // Thrust rebuilt from the throttles stays inside the a-priori thrust interval.
    let flying = records.iter().filter(|r| r.t_s > 0.0);
    let (lo, hi) = flying.fold((f64::INFINITY, 0.0f64), |(lo, hi), r| {
        (lo.min(r.thrust_N), hi.max(r.thrust_N))
    });
    assert!(
        lo >= f64::from(bounds.thrust_min) && hi <= f64::from(bounds.thrust_max),
        "{lo} {hi} vs {bounds:?}"
    );
    // The 20 Hz estimate is compared with the truth at its own time.
    let est: Vec<f64> = records
        .iter()
        .filter(|r| r.t_s > 10.0)
        .map(|r| r.estimate_error_m)
        .collect();
    assert!(
        est.iter().all(|e| e.is_finite() && *e < 0.01),
        "{:?}",
        est.iter().fold(0.0f64, |m, e| m.max(*e))
    );
}

#[test]
fn a_crash_is_reported_with_the_tick() {
    let (s, records) = fly(scenarios::paper(1), Fault::Crash(50_000));
    let e = format!("{:#}", s.unwrap_err());
    assert!(e.contains("closed at t = 50000 us"), "{e}");
    assert_eq!(records.len(), 5);
}

#[test]
fn a_stall_is_reported_with_the_tick() {
    let (s, _) = fly(scenarios::paper(1), Fault::Hang(30_000));
    let e = format!("{:#}", s.unwrap_err());
    assert!(e.contains("stall at t = 30000 us"), "{e}");
}

#[test]
fn an_answer_for_another_time_is_an_error() {
    let (s, _) = fly(scenarios::paper(1), Fault::WrongTime(20_000));
    let e = format!("{:#}", s.unwrap_err());
    assert!(
        e.contains("for t = 20001 us while waiting for t = 20000 us"),
        "{e}"
    );
}

#[test]
fn run_refuses_a_missing_elf_and_a_slow_imu() {
    let options = super::PilOptions {
        elf: "/nonexistent/firmware-mps2-an386".into(),
        qemu: "qemu-system-arm".into(),
        out: std::env::temp_dir().join("pil-unit-never-written"),
        timeout: Duration::from_secs(1),
        send_chunking: super::SendChunking::Whole,
        motor_order: firmware::motor_order::MotorOrder::Mixer,
        record_telemetry: false,
        gcs_udp: None,
    };
    let e = super::run(&scenarios::paper(1), &options, |_| {}).unwrap_err();
    assert!(format!("{e:#}").contains("firmware ELF not found"), "{e:#}");
    let mut slow = scenarios::paper(1);
    slow.imu.rate_hz = 500.0;
    let e = super::run(&slow, &options, |_| {}).unwrap_err();
    assert!(format!("{e:#}").contains("IMU at 1 kHz"), "{e:#}");
}

/// Given a PIL run with a ground station on UDP (a socket on localhost) that asked for
/// AUTOPILOT_VERSION and also sent a cut frame before the run, then: the firmware receives the
/// request whole, right before a `HIL_SENSOR`, and otherwise exactly the bytes of the run
/// without a ground station (same lockstep, same flight); the cut datagram is counted and
/// never sent; the ground station gets the firmware's heartbeat, the version and the
/// acknowledgement in datagrams of whole frames, and none of the lockstep answers.
#[test]
fn a_ground_station_on_udp_talks_to_the_firmware_between_the_lockstep_frames() {
    use crate::harness::gcs_udp::{GcsUdp, MAX_DATAGRAM};
    use firmware::link::mavlink::dialects::common::{MavCmd, COMMAND_LONG_DATA};
    use std::net::UdpSocket;

    let mut setup = scenarios::paper(1);
    setup.hold_s = 0.2;
    setup.duration_s = 0.3;
    let (_, alone) = fly_recording(&setup, SendChunking::Whole);

    let station = UdpSocket::bind("127.0.0.1:0").unwrap();
    station
        .set_read_timeout(Some(Duration::from_millis(200)))
        .unwrap();
    let gcs = GcsUdp::open(station.local_addr().unwrap(), false).unwrap();
    let vehicle = ("127.0.0.1", gcs.local_addr().unwrap().port());
    let request = MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
        param1: 148.0,
        command: MavCmd::MAV_CMD_REQUEST_MESSAGE,
        target_system: 1,
        target_component: 1,
        ..Default::default()
    });
    let mut buf = [0u8; link::MAX_FRAME];
    let n = link::encode(&request, 255, 190, 0, &mut buf);
    let request = buf[..n].to_vec();
    station.send_to(&request[..n - 4], vehicle).unwrap();
    station.send_to(&request, vehicle).unwrap();

    let pipeline = FlightPipeline::new(&setup.flight).unwrap();
    let boot = pipeline.boot_report();
    let b = pipeline.mixer().effectiveness().cast::<f64>();
    let fake = FakeFirmware::new(pipeline, Fault::None);
    let mut link =
        FirmwareLink::new(fake, &setup.flight, b, Duration::from_millis(1)).with_gcs(gcs);
    sil::fly(&setup, &boot, &b, &mut link, |_| {}).unwrap();
    let c = link.gcs().unwrap().counters();
    assert_eq!((c.datagrams_in, c.frames_in, c.malformed), (2, 1, 1));
    // The 20 Hz state telemetry over 0.5 s, at least.
    assert!(c.datagrams_out >= 5, "{c:?}");
    let sent = link.into_transport().sent;

    // The request went in once, whole, right before a HIL_SENSOR (#107).
    let at = sent
        .windows(request.len())
        .position(|w| w == request.as_slice())
        .expect("the request reached the firmware");
    let next = &sent[at + request.len()..];
    assert_eq!(u32::from_le_bytes([next[7], next[8], next[9], 0]), 107);
    let without = [&sent[..at], &sent[at + request.len()..]].concat();
    assert!(
        without == alone,
        "other bytes than the run without a ground station"
    );

    let mut ids = Vec::new();
    let mut datagram = [0u8; 65_536];
    while let Ok(n) = station.recv(&mut datagram) {
        assert!(n <= MAX_DATAGRAM, "{n} B");
        let mut r = FrameReader::new();
        r.push(&datagram[..n]);
        while let Some((h, m)) = r.next_message() {
            assert_eq!((h.system_id, h.component_id), (1, 1));
            ids.push(firmware::link::mavlink::Message::message_id(&m));
        }
        // Whole frames only, nothing left over.
        assert!(r.pending_bytes().is_empty() && r.counters().malformed == 0);
        assert_eq!(r.counters().discarded, 0);
    }
    assert!(ids.contains(&0), "HEARTBEAT: {ids:?}");
    assert!(ids.contains(&148), "AUTOPILOT_VERSION: {ids:?}");
    assert!(ids.contains(&77), "COMMAND_ACK: {ids:?}");
    assert!(
        !ids.contains(&93) && !ids.contains(&85),
        "lockstep answers: {ids:?}"
    );
}
