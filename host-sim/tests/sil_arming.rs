//! SIL scenario 3: arming is refused while the pose is stale or non-finite, and the motors
//! never spin while disarmed, over random command and sensor sequences (proptest), driving the
//! firmware's flight pipeline through its public API and real MAVLink frames.

use firmware::config::FlightConfig;
use firmware::frames;
use firmware::ground_station;
use firmware::link::mavlink::dialects::common::{MavCmd, MavMessage, ATT_POS_MOCAP_DATA};
use firmware::link::{self, MAX_FRAME};
use firmware::pipeline::{FlightPipeline, ImuSample, MotorOutput};
use firmware::safety::FlightState;
use nalgebra::Vector3;
use proptest::prelude::*;

fn bytes(m: &MavMessage) -> Vec<u8> {
    let mut b = [0u8; MAX_FRAME];
    let n = link::encode(m, 255, 190, 0, &mut b);
    b[..n].to_vec()
}

fn pose(p: [f32; 3], q: [f32; 4]) -> Vec<u8> {
    let [x, y, z] = frames::flip_to_array(&Vector3::from(p));
    bytes(&MavMessage::ATT_POS_MOCAP(ATT_POS_MOCAP_DATA {
        time_usec: 0,
        q,
        x,
        y,
        z,
    }))
}

fn config() -> FlightConfig {
    let mut c = FlightConfig::built();
    c.gyro_calibration_samples = 50;
    c
}

/// Drives a pipeline and checks the motor invariants at every tick.
struct Bench {
    p: FlightPipeline,
    now: u64,
    last_good_pose: Option<u64>,
    last_pose_bad: bool,
}

impl Bench {
    fn new() -> Self {
        Self {
            p: FlightPipeline::new(&config()).unwrap(),
            now: 1_000,
            last_good_pose: None,
            last_pose_bad: false,
        }
    }

    fn imu(&mut self, gyro: [f32; 3], accel: [f32; 3]) {
        self.p.on_imu(&ImuSample {
            gyro_rad_s: gyro,
            accel_m_s2: accel,
            time_us: self.now,
        });
    }

    fn advance(&mut self, us: u64) {
        // IMU keeps coming at 1 kHz, ticks at 100 Hz.
        let end = self.now + us;
        while self.now < end {
            self.now += 1_000;
            self.imu([0.0; 3], [0.0, 0.0, 9.81]);
            if self.now.is_multiple_of(10_000) {
                self.tick();
            }
        }
    }

    fn tick(&mut self) -> MotorOutput {
        let out = self.p.control_tick(self.now);
        check(&out, &self.p);
        out
    }

    fn pose(&mut self, p: [f32; 3], q: [f32; 4]) {
        let finite = p.iter().chain(q.iter()).all(|x| x.is_finite());
        let norm = q.iter().map(|x| x * x).sum::<f32>().sqrt();
        self.p.on_link_bytes(&pose(p, q), self.now);
        if finite && (0.9..=1.1).contains(&norm) {
            self.last_good_pose = Some(self.now);
            self.last_pose_bad = false;
        } else {
            self.last_pose_bad = true;
        }
    }

    fn converge(&mut self) {
        for _ in 0..60 {
            self.advance(10_000);
            self.pose([0.0, 0.0, 1.0], [1.0, 0.0, 0.0, 0.0]);
        }
        assert!(!self.p.status().calibrating && self.p.status().converged);
    }

    /// Sends an arm command; returns whether the vehicle armed, and checks the refusal rule.
    fn arm(&mut self, inverted: bool) -> bool {
        let before = self.p.status().state;
        let stale = self.last_good_pose.is_none_or(|t| self.now - t >= 50_000);
        self.p
            .on_link_bytes(&bytes(&ground_station::arm(inverted)), self.now);
        let armed = before == FlightState::Disarmed && self.p.status().state == FlightState::Armed;
        if armed {
            assert!(!stale, "armed with a stale pose");
            assert!(!self.last_pose_bad, "armed right after a non-finite pose");
        }
        armed
    }
}

fn check(out: &MotorOutput, p: &FlightPipeline) {
    assert!(
        out.throttle
            .iter()
            .all(|u| u.is_finite() && (0.0..=1.0).contains(u)),
        "{out:?}"
    );
    if !out.armed {
        assert_eq!(out.throttle, [0.0; 4], "spinning while disarmed");
    }
    assert_eq!(out.armed, p.status().state != FlightState::Disarmed);
}

#[test]
fn arming_refused_while_pose_stale_or_non_finite() {
    let mut b = Bench::new();
    // Nothing yet: refused.
    assert!(!b.arm(false));
    b.converge();
    // Stale: 60 ms without a pose.
    b.advance(60_000);
    assert!(!b.arm(false));
    assert_eq!(b.p.status().state, FlightState::Disarmed);
    // Non-finite pose: refused, and counted.
    b.pose([f32::NAN, 0.0, 1.0], [1.0, 0.0, 0.0, 0.0]);
    assert!(!b.arm(false));
    assert!(b.p.status().counters.non_finite >= 1);
    // Infinite quaternion: refused.
    b.pose([0.0, 0.0, 1.0], [f32::INFINITY, 0.0, 0.0, 0.0]);
    assert!(!b.arm(false));
    // Fresh and finite: accepted.
    b.pose([0.0, 0.0, 1.0], [1.0, 0.0, 0.0, 0.0]);
    assert!(b.arm(false));
    let out = b.tick();
    assert!(out.armed);
    // Kill stops the motors at the next tick.
    b.p.on_link_bytes(&bytes(&ground_station::kill()), b.now);
    assert_eq!(b.p.status().state, FlightState::Disarmed);
    assert_eq!(b.tick().throttle, [0.0; 4]);
    // Refusals were reported as events and counted.
    assert!(b.p.status().counters.refused_commands >= 3);
}

#[test]
fn arming_upside_down_needs_the_explicit_flag() {
    let mut b = Bench::new();
    let inverted = [0.0, 1.0, 0.0, 0.0];
    for _ in 0..60 {
        b.advance(10_000);
        b.pose([0.0, 0.0, 1.0], inverted);
    }
    assert!(!b.arm(false));
    assert!(b.arm(true));
}

#[derive(Clone, Debug)]
enum Op {
    Imu([f32; 3], [f32; 3]),
    Pose([f32; 3], [f32; 4]),
    Arm(bool),
    Disarm,
    Kill,
    Takeoff(f32),
    Land,
    Mission,
    Wait(u64),
    Tick,
    Garbage(Vec<u8>),
}

fn value() -> impl Strategy<Value = f32> {
    prop_oneof![
        8 => -3.0f32..3.0,
        1 => Just(f32::NAN),
        1 => Just(f32::INFINITY),
        1 => Just(f32::NEG_INFINITY),
    ]
}

fn op() -> impl Strategy<Value = Op> {
    prop_oneof![
        3 => (prop::array::uniform3(value()), prop::array::uniform3(value())).prop_map(|(g, a)| Op::Imu(g, a)),
        4 => (prop::array::uniform3(value()), prop::array::uniform4(value())).prop_map(|(p, q)| Op::Pose(p, q)),
        2 => Just(Op::Pose([0.0, 0.0, 1.0], [1.0, 0.0, 0.0, 0.0])),
        2 => any::<bool>().prop_map(Op::Arm),
        1 => Just(Op::Disarm),
        1 => Just(Op::Kill),
        1 => (0.1f32..3.0).prop_map(Op::Takeoff),
        1 => Just(Op::Land),
        1 => Just(Op::Mission),
        3 => (1u64..200_000).prop_map(Op::Wait),
        3 => Just(Op::Tick),
        1 => prop::collection::vec(any::<u8>(), 0..64).prop_map(Op::Garbage),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// After calibration and convergence, any sequence: the motors never spin while disarmed,
    /// no throttle is NaN or outside [0, 1], and an arm is only accepted with a fresh, finite
    /// pose.
    #[test]
    fn motors_never_spin_while_disarmed(ops in prop::collection::vec(op(), 1..120)) {
        let mut b = Bench::new();
        b.converge();
        for o in ops {
            match o {
                Op::Imu(g, a) => b.imu(g, a),
                Op::Pose(p, q) => b.pose(p, q),
                Op::Arm(inv) => { b.arm(inv); }
                Op::Disarm => b.p.on_link_bytes(&bytes(&ground_station::command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 0.0, 0.0, 0.0)), b.now),
                Op::Kill => {
                    b.p.on_link_bytes(&bytes(&ground_station::kill()), b.now);
                    prop_assert_eq!(b.p.status().state, FlightState::Disarmed);
                }
                Op::Takeoff(h) => b.p.on_link_bytes(&bytes(&ground_station::takeoff(h)), b.now),
                Op::Land => b.p.on_link_bytes(&bytes(&ground_station::land()), b.now),
                Op::Mission => b.p.on_link_bytes(&bytes(&ground_station::mission_start()), b.now),
                Op::Wait(us) => b.advance(us),
                Op::Tick => { b.now += 1; b.tick(); }
                Op::Garbage(g) => b.p.on_link_bytes(&g, b.now),
            }
            let mut buf = [0u8; 512];
            let n = b.p.telemetry(b.now, &mut buf);
            prop_assert!(n <= buf.len());
            while b.p.take_events().is_some() {}
        }
    }
}
