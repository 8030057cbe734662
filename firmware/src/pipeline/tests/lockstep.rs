//! The lockstep rule on the whole pipeline (`hil` feature): a realistic processor-in-the-loop
//! stream (a `HIL_SENSOR` every 1 ms, motion-capture poses at 100 Hz, an arm and a mission
//! start), fed in different chunkings, gives the same ticks, throttles and telemetry bytes.

use proptest::prelude::*;

use crate::ground_station;
use crate::link;
use crate::pipeline::lockstep::Lockstep;
use crate::pipeline::*;
use mavlink::dialects::common::{
    HilActuatorControlsFlags, HilSensorUpdatedFlags, MavMessage, ATT_POS_MOCAP_DATA,
    HIL_ACTUATOR_CONTROLS_DATA, HIL_SENSOR_DATA, POSITION_TARGET_LOCAL_NED_DATA,
};
use mavlink::{MavlinkVersion, MessageData};

/// Length of the stream \[ms\].
const STREAM_MS: u64 = 2_000;
/// When the arm and the mission start are sent \[ms\].
const ARM_MS: u64 = 700;
const MISSION_MS: u64 = 900;

/// splitmix64: a tiny seeded generator for the IMU noise and the read sizes.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [-a, a].
    fn noise(&mut self, a: f32) -> f32 {
        ((self.next() >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0) * a
    }
}

fn put(m: &MavMessage, seq: &mut u8, out: &mut Vec<u8>) {
    let mut b = [0u8; link::MAX_FRAME];
    let n = link::encode(m, 255, 190, *seq, &mut b);
    assert!(n > 0);
    *seq = seq.wrapping_add(1);
    out.extend_from_slice(&b[..n]);
}

/// What `host-sim pil` sends, in its order: for every 1 ms step `t`, the link bytes due at `t`
/// (a pose every 10 ms, 3 ms after the ticks; the commands), then the `HIL_SENSOR` at `t`.
/// The poses move (a slow sway) so that a pose dated differently changes the estimate.
fn pil_stream() -> Vec<u8> {
    let mut rng = Rng(7);
    let mut seq = 0u8;
    let mut out = Vec::new();
    for ms in 0..=STREAM_MS {
        let t = ms as f32 * 1e-3;
        if ms % 10 == 3 {
            let sway = libm::sinf(2.0 * core::f32::consts::PI * 0.7 * t);
            let m = MavMessage::ATT_POS_MOCAP(ATT_POS_MOCAP_DATA {
                time_usec: ms * 1000,
                q: [1.0, 0.0, 0.0, 0.0],
                x: 0.05 * sway,
                y: -0.03 * sway,
                z: -1.0 - 0.1 * sway,
            });
            put(&m, &mut seq, &mut out);
        }
        if ms == ARM_MS {
            put(&ground_station::arm(false), &mut seq, &mut out);
        }
        if ms == MISSION_MS {
            put(&ground_station::mission_start(), &mut seq, &mut out);
        }
        let m = MavMessage::HIL_SENSOR(HIL_SENSOR_DATA {
            time_usec: ms * 1000,
            xacc: rng.noise(0.2),
            yacc: rng.noise(0.2),
            zacc: -9.81 + rng.noise(0.2),
            xgyro: 0.01 + rng.noise(0.02),
            ygyro: -0.02 + rng.noise(0.02),
            zgyro: 0.005 + rng.noise(0.02),
            fields_updated: HilSensorUpdatedFlags::from_bits_retain(link::HIL_SENSOR_IMU_FIELDS),
            ..Default::default()
        });
        put(&m, &mut seq, &mut out);
    }
    out
}

/// Every message of type `D` in `telemetry` (unsigned MAVLink 2 frames, back to back).
fn messages<D: MessageData>(telemetry: &[u8]) -> Vec<D> {
    let mut out = Vec::new();
    let mut i = 0;
    while i + 12 <= telemetry.len() {
        let len = usize::from(telemetry[i + 1]);
        let id = u32::from_le_bytes([telemetry[i + 7], telemetry[i + 8], telemetry[i + 9], 0]);
        if id == D::ID {
            out.push(D::deser(MavlinkVersion::V2, &telemetry[i + 10..i + 10 + len]).unwrap());
        }
        i += 12 + len;
    }
    out
}

/// The x500 build with a short gyro calibration, so that it arms within the stream.
fn pipeline() -> FlightPipeline {
    let mut c = FlightConfig::built();
    c.gyro_calibration_samples = 200;
    FlightPipeline::new(&c).unwrap()
}

/// One run: each tick's time and throttles, and every telemetry byte, in order.
#[derive(Debug, PartialEq)]
struct Run {
    ticks: Vec<(u64, MotorOutput)>,
    telemetry: Vec<u8>,
}

impl Run {
    fn tick(&mut self, p: &mut FlightPipeline, now_us: u64) {
        let out = p.control_tick(now_us);
        // As `app::control::run`: at most 512 bytes per tick.
        let mut buf = [0u8; 512];
        let n = p.telemetry(now_us, &mut buf);
        self.ticks.push((now_us, out));
        self.telemetry.extend_from_slice(&buf[..n]);
    }
}

/// How `a` differs from `b`, in a line (`None`: identical): the ticks that differ, the
/// largest throttle difference, the first telemetry byte that differs.
fn difference(a: &Run, b: &Run) -> Option<String> {
    if a == b {
        return None;
    }
    let differing = a.ticks.iter().zip(&b.ticks).filter(|(x, y)| x != y);
    let max = differing
        .clone()
        .flat_map(|(x, y)| {
            x.1.throttle
                .iter()
                .zip(y.1.throttle)
                .map(|(u, v)| (u - v).abs())
        })
        .fold(0.0f32, f32::max);
    let first_byte = a
        .telemetry
        .iter()
        .zip(&b.telemetry)
        .position(|(x, y)| x != y);
    Some(format!(
        "{} vs {} ticks, {} differ (first at t = {:?} us), throttles up to {max:e} apart; \
         telemetry {} vs {} bytes, first difference at byte {first_byte:?}",
        a.ticks.len(),
        b.ticks.len(),
        differing.clone().count(),
        differing.clone().next().map(|(x, _)| x.0),
        a.telemetry.len(),
        b.telemetry.len(),
    ))
}

/// Read sizes \[bytes\]: `sizes` cycled (0 counts as 1).
fn cycle(sizes: &[usize]) -> impl FnMut() -> usize + '_ {
    let mut k = 0;
    move || {
        k += 1;
        sizes[(k - 1) % sizes.len()].max(1)
    }
}

/// Random read sizes in 1..=`max` from `seed`.
fn random(seed: u64, max: u64) -> impl FnMut() -> usize {
    let mut rng = Rng(seed);
    move || (rng.next() % max + 1) as usize
}

/// The stream through `app::control::LockstepClock`'s logic ([`Lockstep`] with its 128-byte
/// buffer), each read taking `read()` bytes (at most what the buffer offers).
fn run_lockstep(stream: &[u8], read: impl FnMut() -> usize) -> Run {
    run_lockstep_on(pipeline(), stream, read)
}

/// [`run_lockstep`] on a given pipeline.
fn run_lockstep_on(mut p: FlightPipeline, stream: &[u8], mut read: impl FnMut() -> usize) -> Run {
    let period = p.config().control_rate.period_us();
    let mut lock = Lockstep::<128>::new(period);
    let mut run = Run {
        ticks: Vec::new(),
        telemetry: Vec::new(),
    };
    let mut at = 0;
    loop {
        while let Some(t) = lock.advance(&mut p) {
            run.tick(&mut p, t);
        }
        if at == stream.len() {
            return run;
        }
        let space = lock.space();
        let n = read().min(space.len()).min(stream.len() - at);
        space[..n].copy_from_slice(&stream[at..at + n]);
        lock.filled(n);
        at += n;
    }
}

/// The clock before the lockstep rule, for comparison: each read stamped with the clock known
/// before it, and a tick only checked between reads.
fn run_old_rule(stream: &[u8], mut read: impl FnMut() -> usize) -> Run {
    let mut p = pipeline();
    let period = p.config().control_rate.period_us();
    let mut deadline: Option<u64> = None;
    let mut run = Run {
        ticks: Vec::new(),
        telemetry: Vec::new(),
    };
    let mut at = 0;
    loop {
        if let Some(t) = p.hil_time_us() {
            if t >= *deadline.get_or_insert(t) {
                deadline = Some(t + period);
                run.tick(&mut p, t);
                continue;
            }
        }
        if at == stream.len() {
            return run;
        }
        let n = read().min(128).min(stream.len() - at);
        let stamp = p.hil_time_us().unwrap_or(0);
        p.on_link_bytes(&stream[at..at + n], stamp);
        at += n;
    }
}

/// The reference run (one byte per read) really flies: a tick every 10 ms, armed after the
/// arm command, throttles that change from tick to tick in the mission, and every tick's
/// `HIL_ACTUATOR_CONTROLS` carries the LOCKSTEP flag. Otherwise the comparisons below would
/// compare idle motors.
#[test]
fn the_stream_arms_and_flies_with_lockstep_actuator_frames() {
    let stream = pil_stream();
    let run = run_lockstep(&stream, cycle(&[1]));
    assert_eq!(run.ticks.len() as u64, STREAM_MS / 10 + 1);
    assert!(run
        .ticks
        .iter()
        .enumerate()
        .all(|(k, (t, _))| *t == k as u64 * 10_000));
    let armed: Vec<_> = run.ticks.iter().filter(|(_, o)| o.armed).collect();
    assert!(armed.len() > 100, "armed for {} ticks", armed.len());
    let flying: Vec<[f32; 4]> = run
        .ticks
        .iter()
        .filter(|(t, _)| *t > (MISSION_MS + 20) * 1000)
        .map(|(_, o)| o.throttle)
        .collect();
    assert!(flying.windows(2).filter(|w| w[0] != w[1]).count() > 50);
    // Every actuator frame says LOCKSTEP.
    let actuators: Vec<HIL_ACTUATOR_CONTROLS_DATA> = messages(&run.telemetry);
    assert!(actuators
        .iter()
        .all(|a| a.flags == HilActuatorControlsFlags::HIL_ACTUATOR_CONTROLS_FLAGS_LOCKSTEP));
    assert_eq!(actuators.len(), run.ticks.len());
    // The reference sent with each tick is the whole reference: during the helix its velocity
    // matches the change of its position between ticks (an independent finite difference),
    // and its yaw the change of yaw.
    let targets: Vec<POSITION_TARGET_LOCAL_NED_DATA> = messages(&run.telemetry);
    assert!(targets.iter().all(|m| m.type_mask.is_empty()));
    let helix: Vec<_> = targets
        .iter()
        .filter(|m| u64::from(m.time_boot_ms) > MISSION_MS + 20)
        .collect();
    assert!(helix.len() > 50);
    let mut moving = 0;
    for w in helix.windows(2) {
        let dt = 0.010;
        let fd = [
            (w[1].x - w[0].x) / dt,
            (w[1].y - w[0].y) / dt,
            (w[1].z - w[0].z) / dt,
        ];
        let mean = [
            0.5 * (w[0].vx + w[1].vx),
            0.5 * (w[0].vy + w[1].vy),
            0.5 * (w[0].vz + w[1].vz),
        ];
        for k in 0..3 {
            assert!((fd[k] - mean[k]).abs() < 2e-2, "{fd:?} vs {mean:?}");
        }
        let yaw_fd = (w[1].yaw - w[0].yaw) / dt;
        assert!((yaw_fd - 0.5 * (w[0].yaw_rate + w[1].yaw_rate)).abs() < 2e-2);
        moving += usize::from(mean.iter().any(|v: &f32| v.abs() > 0.05));
    }
    assert!(moving > 40, "the reference moves: {moving}");
}

/// Given the same stream, when it is read whole (as much as the buffer takes), one byte at a
/// time, or in random sizes from several seeds, then every tick (time, throttles) and every
/// telemetry byte is the same.
#[test]
fn ticks_and_telemetry_do_not_depend_on_the_chunking() {
    let stream = pil_stream();
    let reference = run_lockstep(&stream, cycle(&[1]));
    let whole = run_lockstep(&stream, cycle(&[usize::MAX]));
    assert_eq!(difference(&whole, &reference), None, "whole reads");
    let fixed = run_lockstep(&stream, cycle(&[64]));
    assert_eq!(difference(&fixed, &reference), None, "64-byte reads");
    for seed in 1..=4 {
        let random = run_lockstep(&stream, random(seed, 200));
        assert_eq!(difference(&random, &reference), None, "seed {seed}");
    }
}

/// The old rule (a read stamped with the clock before it, ticks between reads) is what this
/// test guards against: it gives the same as the lockstep rule only with one byte per read,
/// and other throttles with reads of up to 64 bytes.
#[test]
fn the_old_rule_depended_on_the_chunking() {
    let stream = pil_stream();
    let reference = run_lockstep(&stream, cycle(&[1]));
    assert_eq!(run_old_rule(&stream, cycle(&[1])), reference);
    let chunked = run_old_rule(&stream, random(3, 64));
    assert_eq!(chunked.ticks.len(), reference.ticks.len());
    let differing = chunked
        .ticks
        .iter()
        .zip(&reference.ticks)
        .filter(|(a, b)| a != b)
        .count();
    assert!(differing > 10, "{:?}", difference(&chunked, &reference));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]

    /// Any sequence of read sizes gives the one-byte run's ticks and telemetry.
    #[test]
    fn any_read_sizes_give_the_same_run(sizes in prop::collection::vec(1usize..300, 1..40)) {
        let stream = pil_stream();
        let reference = run_lockstep(&stream, cycle(&[1]));
        let run = run_lockstep(&stream, cycle(&sizes));
        prop_assert_eq!(difference(&run, &reference), None);
    }
}

/// Given the x500 (its file in PX4's order) built with `FIRMWARE_HIL_MOTOR_ORDER=betaflight`,
/// when it flies the stream, then each actuator frame carries the mixer's throttles in
/// Betaflight's quad X order: rear-right, front-right, rear-left, front-left = rotors 3, 0, 1, 2.
#[test]
fn hil_outputs_in_betaflight_order() {
    let mut c = FlightConfig::built();
    c.gyro_calibration_samples = 200;
    c.hil_motor_order = crate::motor_order::MotorOrder::Betaflight;
    let run = run_lockstep_on(
        FlightPipeline::new(&c).unwrap(),
        &pil_stream(),
        cycle(&[128]),
    );
    let frames: Vec<HIL_ACTUATOR_CONTROLS_DATA> = messages(&run.telemetry);
    assert_eq!(frames.len(), run.ticks.len());
    let mut distinct = 0;
    for (f, (_, out)) in frames.iter().zip(&run.ticks) {
        let u = out.throttle;
        assert_eq!(&f.controls[..4], &[u[3], u[0], u[1], u[2]]);
        distinct += usize::from(u[0] != u[3]);
    }
    // The permutation is visible: rotors differ in flight.
    assert!(distinct > 50, "{distinct}");
}
