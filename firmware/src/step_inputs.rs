//! Deterministic inputs of the control step, and the step itself, shared by the Cortex-M4F
//! instruction-count bench (`src/bin/step_bench`, under QEMU), the host criterion bench
//! (`benches/steps.rs`) and host-sim's ARM-vs-host comparison (`host-sim m4f-bench`).
//!
//! **One full step** is what the control task does every 10 ms ([`full_step`]): the IMU samples
//! received since the last tick ([`IMU_PER_TICK`] at 1 kHz, [`FlightPipeline::on_imu`]), the link
//! bytes (a MAVLink 2 `ATT_POS_MOCAP` pose frame, plus commands on the arming tick,
//! [`FlightPipeline::on_link_bytes`]), then [`FlightPipeline::control_tick`] (estimate → safety →
//! reference → controller-core law → mixer → thrust curve). **One controller step** is
//! [`controller_core::Controller::step`] alone ([`controller_step`]) on `f32` states and
//! references along the same trajectory.
//!
//! The sequence ([`StepSequence`]) follows the software-in-the-loop paper scenario: the vehicle
//! rests upside down (roll −179°, yaw 100°) at `(5, 5, 10) m` NWU, 9.2 m from the helix, while
//! the gyro calibrates (1000 samples); at tick [`ARM_TICK`] the ground station sends the explicit
//! upside-down arm and the helix mission start; then [`FLIGHT_TICKS`] ticks of flight. The flight
//! is **open loop**: the vehicle follows a scripted trajectory (it rights itself over 0.8 s,
//! with a small roll wobble; its position error to the helix and its yaw error decay
//! exponentially), so every flight tick runs the real path (armed, helix mode, controller
//! running, mixer allocating). The IMU samples are consistent with that trajectory (body rates
//! and specific force), with the SIL scenario's gyro and accelerometer biases and a small
//! deterministic noise; poses carry 10 ms of latency.
//!
//! Determinism: the inputs are built with IEEE-754 `f32` arithmetic, integer arithmetic and
//! `libm`'s `f32` functions only (the same Rust code on both targets; never the host's C
//! library), so they are bit-identical on the Cortex-M4F and on the host. The *outputs* may
//! differ in the last bits, because the step itself calls `sin`/`cos`/`atan2` through nalgebra,
//! which uses `libm` on the MCU and the host's C library under `std`.
//!
//! Frames and units as everywhere in the firmware: inertial NWU (z up), body FLU, SI units.

use controller_core::{
    ControlOutput, Controller, ReferenceSample, ReferenceTrajectory, StepError, Trajectory,
    VehicleState,
};
use mavlink::dialects::common::{MavCmd, ATT_POS_MOCAP_DATA, COMMAND_LONG_DATA};
use mavlink::{MAVLinkV2MessageRaw, MavHeader, MessageData};
use nalgebra::{Quaternion, UnitQuaternion, Vector2, Vector3};

use crate::config::FlightConfig;
use crate::frames;
use crate::pipeline::{FlightPipeline, ImuSample, MotorOutput};
use crate::safety::FlightState;

/// Control period \[µs\] (100 Hz, `FlightConfig::paper().control_period`).
pub const TICK_US: u64 = 10_000;
/// IMU samples per control tick (1 kHz IMU).
pub const IMU_PER_TICK: usize = 10;
/// The tick (1-based; tick `n` runs at `n · TICK_US`) that carries the arm and mission-start
/// commands. The gyro calibration (1000 still samples) ends at tick 100.
pub const ARM_TICK: u32 = 110;
/// Flight ticks after the arming tick (3 s of flight).
pub const FLIGHT_TICKS: u32 = 300;
/// All ticks of the sequence.
pub const TOTAL_TICKS: u32 = ARM_TICK + FLIGHT_TICKS;
/// Room for the link bytes of one tick \[bytes\]: a pose frame (48 B) and two `COMMAND_LONG`
/// frames (≤ 45 B each).
pub const LINK_CAPACITY: usize = 160;
/// Controller sampling period \[s\] of the controller-alone steps.
pub const CONTROLLER_DT: f32 = 0.01;

/// Pose latency \[µs\] (as configured: `FlightConfig::paper().mocap_latency_us`).
const POSE_LATENCY_US: u64 = 10_000;
/// Arming time \[µs\]; the helix starts here (flight time `t = 0`).
const ARM_US: u64 = ARM_TICK as u64 * TICK_US;
/// Resting position \[m\] NWU (the paper's initial position).
const REST_POSITION: [f32; 3] = [5.0, 5.0, 10.0];
/// Resting roll \[rad\] (−179°) and yaw \[rad\] (100°), `R = Rz(yaw) Rx(roll)`.
const REST_ROLL: f32 = -179.0 * core::f32::consts::PI / 180.0;
const REST_YAW: f32 = 100.0 * core::f32::consts::PI / 180.0;
/// Time to right the vehicle \[s\], roll wobble amplitude \[rad\] and angular frequency [rad/s].
const RIGHTING_S: f32 = 0.8;
const WOBBLE: f32 = 0.05;
const WOBBLE_RATE: f32 = 5.0;
/// Decay times of the position error and of the yaw error \[s\].
const POSITION_DECAY_S: f32 = 1.0;
const YAW_DECAY_S: f32 = 0.5;
/// Gyro bias [rad/s] and accelerometer bias [m/s²] (the SIL IMU model's), and the
/// half-widths of the uniform noise: gyro [rad/s], accelerometer [m/s²], pose position \[m\].
const GYRO_BIAS: [f32; 3] = [0.01, -0.02, 0.015];
const ACCEL_BIAS: [f32; 3] = [0.05, -0.03, 0.08];
const GYRO_NOISE: f32 = 3e-3;
const ACCEL_NOISE: f32 = 0.05;
const POSE_NOISE: f32 = 5e-4;
/// Gravity [m/s²] (the paper vehicle's).
const GRAVITY: f32 = 9.81;
/// Helix angular frequency `f = 2π/15` [rad/s] (rounded from f64 like controller-core's).
const HELIX_RATE: f32 = (2.0 * core::f64::consts::PI / 15.0) as f32;
/// Ground station ids.
const GCS_SYSTEM: u8 = 255;
const GCS_COMPONENT: u8 = 190;

/// What a tick of the sequence does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// Disarmed on the ground, gyro calibrating then estimator converging (not measured).
    Setup,
    /// The tick that carries the arm (upside down, explicit) and mission-start commands.
    Arm,
    /// Armed, flying the helix: the measured steps.
    Flight,
}

/// Everything one full control step consumes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepInputs {
    /// Tick number (1-based).
    pub tick: u32,
    /// Tick time \[µs\].
    pub now_us: u64,
    /// Phase of the sequence.
    pub phase: Phase,
    /// The IMU samples since the last tick (body FLU), oldest first.
    pub imu: [ImuSample; IMU_PER_TICK],
    /// The link bytes received since the last tick (`link[..link_len]`).
    pub link: [u8; LINK_CAPACITY],
    /// Number of valid bytes in `link`.
    pub link_len: usize,
}

/// Everything one controller step consumes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ControllerInputs {
    /// Measured state (inertial NWU `p` \[m\], `v` [m/s]; FLU→NWU attitude; body `ω` [rad/s]).
    pub state: VehicleState<f32>,
    /// The paper's helix reference at the same time.
    pub reference: ReferenceSample<f32>,
    /// Sampling period \[s\].
    pub dt: f32,
}

/// The figures compared between the MCU and the host after a full step: the four throttles
/// (\[0, 1\], mixer order), then the collective thrust \[N\] and body torque [N m] (FLU) the
/// mixer's rotor thrusts achieve (equal to the controller's when nothing saturates; zeros when
/// the mixer did not run).
pub type FullOutputs = [f32; 8];

/// The figures compared after a controller step: thrust \[N\] and body torque [N m] (FLU).
pub type ControllerOutputs = [f32; 4];

/// The scripted vehicle state at one instant (NWU / FLU, SI).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Truth {
    /// Position \[m\].
    pub position: Vector3<f32>,
    /// Velocity [m/s].
    pub velocity: Vector3<f32>,
    /// Acceleration [m/s²].
    pub acceleration: Vector3<f32>,
    /// Attitude, FLU body to NWU.
    pub attitude: UnitQuaternion<f32>,
    /// Body angular velocity [rad/s].
    pub angular_velocity: Vector3<f32>,
    /// Specific force in the body [m/s²] (what a perfect accelerometer reads).
    pub specific_force: Vector3<f32>,
}

/// Derivatives 0..=2 of the helix position \[m\], [m/s], [m/s²] at flight time `t` \[s\]
/// (`(−3, 1, 4.5) + (cos f t, sin f t, cos f t)`), with `libm`.
fn helix_position(t: f32) -> [Vector3<f32>; 5] {
    let f = HELIX_RATE;
    let (s, c) = libm::sincosf(f * t);
    let mut d = [Vector3::zeros(); 5];
    let mut scale = 1.0f32;
    let phases = [(s, c), (c, -s), (-s, -c), (-c, s), (s, c)];
    for (n, (ps, pc)) in phases.iter().enumerate() {
        d[n] = Vector3::new(scale * pc, scale * ps, scale * pc);
        scale *= f;
    }
    d[0] += Vector3::new(-3.0, 1.0, 4.5);
    d
}

/// The paper's helix reference (`ψ_d = π sin(f t)`) at flight time `t` \[s\], computed with
/// `libm` so that it is bit-identical on both targets (controller-core's
/// `ReferenceTrajectory::paper_helix` gives the same up to the last bits of `sin`/`cos`).
pub fn helix_reference(t: f32) -> ReferenceSample<f32> {
    let d = helix_position(t);
    let (psi, rate, acc) = helix_yaw(t);
    let (s, c) = libm::sincosf(psi);
    let nu = Vector2::new(c, s);
    let perp = Vector2::new(-s, c);
    ReferenceSample {
        position: d[0],
        velocity: d[1],
        acceleration: d[2],
        jerk: d[3],
        snap: d[4],
        heading: nu,
        heading_rate: perp * rate,
        heading_acceleration: perp * acc - nu * (rate * rate),
    }
}

/// `(ψ_d, ψ̇_d, ψ̈_d)` of the helix at `t` \[s\]: rad, rad/s, rad/s².
fn helix_yaw(t: f32) -> (f32, f32, f32) {
    let f = HELIX_RATE;
    let a = core::f32::consts::PI;
    let (s, c) = libm::sincosf(f * t);
    (a * s, a * f * c, -a * f * f * s)
}

/// The scripted state at `time_us` (same clock as the ticks): at rest upside down before the
/// arming tick; then righting itself onto the helix (see the module docs).
pub fn truth(time_us: u64) -> Truth {
    let rest = Vector3::from(REST_POSITION);
    let (position, velocity, acceleration, roll, roll_rate, yaw, yaw_rate) = if time_us <= ARM_US {
        let z = Vector3::zeros();
        (rest, z, z, REST_ROLL, 0.0, REST_YAW, 0.0)
    } else {
        let t = (time_us - ARM_US) as u32 as f32 * 1e-6;
        let h = helix_position(t);
        let e0 = rest - helix_position(0.0)[0];
        let d = libm::expf(-t / POSITION_DECAY_S);
        let k = 1.0 / POSITION_DECAY_S;
        let position = h[0] + e0 * d;
        let velocity = h[1] - e0 * (k * d);
        let acceleration = h[2] + e0 * (k * k * d);
        let (blend, blend_rate) = if t < RIGHTING_S {
            let w = core::f32::consts::PI / RIGHTING_S;
            let (s, c) = libm::sincosf(w * t);
            (0.5 * (1.0 + c), -0.5 * w * s)
        } else {
            (0.0, 0.0)
        };
        let (ws, wc) = libm::sincosf(WOBBLE_RATE * t);
        let roll = REST_ROLL * blend + WOBBLE * ws;
        let roll_rate = REST_ROLL * blend_rate + WOBBLE * WOBBLE_RATE * wc;
        let (psi_d, psi_d_rate, _) = helix_yaw(t);
        let dy = REST_YAW - helix_yaw(0.0).0;
        let e = libm::expf(-t / YAW_DECAY_S);
        let yaw = psi_d + dy * e;
        let yaw_rate = psi_d_rate - dy / YAW_DECAY_S * e;
        (
            position,
            velocity,
            acceleration,
            roll,
            roll_rate,
            yaw,
            yaw_rate,
        )
    };
    // R = Rz(ψ) Rx(φ): q = (cz cx, cz sx, sz sx, sz cx) with half angles.
    let (sx, cx) = libm::sincosf(0.5 * roll);
    let (sz, cz) = libm::sincosf(0.5 * yaw);
    let attitude =
        UnitQuaternion::new_unchecked(Quaternion::new(cz * cx, cz * sx, sz * sx, sz * cx));
    // ω (body) = Rxᵀ(φ) ψ̇ e₃ + φ̇ e₁ = (φ̇, sin φ ψ̇, cos φ ψ̇).
    let (sr, cr) = libm::sincosf(roll);
    let angular_velocity = Vector3::new(roll_rate, sr * yaw_rate, cr * yaw_rate);
    // Specific force (body) = Rᵀ (a + g e₃) = Rx(−φ) Rz(−ψ) (a + g e₃).
    let (sy, cy) = libm::sincosf(yaw);
    let w = acceleration + Vector3::new(0.0, 0.0, GRAVITY);
    let u = Vector3::new(cy * w.x + sy * w.y, -sy * w.x + cy * w.y, w.z);
    let specific_force = Vector3::new(u.x, cr * u.y + sr * u.z, -sr * u.y + cr * u.z);
    Truth {
        position,
        velocity,
        acceleration,
        attitude,
        angular_velocity,
        specific_force,
    }
}

/// Xorshift32 noise in `[−1, 1)` (integer arithmetic and an exact conversion: deterministic).
#[derive(Clone, Copy, Debug)]
struct Noise(u32);

impl Noise {
    fn next(&mut self) -> f32 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        self.0 = x;
        // 24 random bits, exactly representable: k · 2⁻²³ − 1 ∈ [−1, 1).
        (x >> 8) as f32 * (1.0 / 8_388_608.0) - 1.0
    }

    fn vector(&mut self, half_width: f32) -> Vector3<f32> {
        let x = self.next();
        let y = self.next();
        let z = self.next();
        Vector3::new(x, y, z) * half_width
    }
}

/// Writes a MAVLink 2 frame of `message` from the ground station into `out` at `*len`.
fn put<D: MessageData>(message: &D, sequence: &mut u8, out: &mut [u8], len: &mut usize) {
    let mut raw = MAVLinkV2MessageRaw::new();
    raw.serialize_message_data(
        MavHeader {
            system_id: u32::from(GCS_SYSTEM),
            component_id: GCS_COMPONENT,
            sequence: *sequence,
        },
        message,
    );
    *sequence = sequence.wrapping_add(1);
    let bytes = raw.raw_bytes();
    out[*len..*len + bytes.len()].copy_from_slice(bytes);
    *len += bytes.len();
}

fn command(command: MavCmd, param1: f32, param2: f32) -> COMMAND_LONG_DATA {
    COMMAND_LONG_DATA {
        param1,
        param2,
        param3: 0.0,
        param4: 0.0,
        param5: 0.0,
        param6: 0.0,
        param7: 0.0,
        command,
        target_system: 1,
        target_component: 1,
        confirmation: 0,
    }
}

/// The deterministic sequence of [`TOTAL_TICKS`] full-step inputs (an iterator).
#[derive(Clone, Debug)]
pub struct StepSequence {
    tick: u32,
    sequence: u8,
    noise: Noise,
}

impl Default for StepSequence {
    fn default() -> Self {
        Self::new()
    }
}

impl StepSequence {
    /// The sequence from its first tick.
    pub fn new() -> Self {
        Self {
            tick: 0,
            sequence: 0,
            noise: Noise(0x2545_F491),
        }
    }
}

impl Iterator for StepSequence {
    type Item = StepInputs;

    fn next(&mut self) -> Option<StepInputs> {
        if self.tick >= TOTAL_TICKS {
            return None;
        }
        self.tick += 1;
        let tick = self.tick;
        let now_us = u64::from(tick) * TICK_US;
        let phase = match tick {
            t if t < ARM_TICK => Phase::Setup,
            ARM_TICK => Phase::Arm,
            _ => Phase::Flight,
        };
        let gyro_bias = Vector3::from(GYRO_BIAS);
        let accel_bias = Vector3::from(ACCEL_BIAS);
        let mut imu = [ImuSample {
            gyro_rad_s: [0.0; 3],
            accel_m_s2: [0.0; 3],
            time_us: 0,
        }; IMU_PER_TICK];
        let step_us = TICK_US / IMU_PER_TICK as u64;
        for (i, s) in imu.iter_mut().enumerate() {
            let time_us = now_us - TICK_US + (i as u64 + 1) * step_us;
            let x = truth(time_us);
            let g = x.angular_velocity + gyro_bias + self.noise.vector(GYRO_NOISE);
            let a = x.specific_force + accel_bias + self.noise.vector(ACCEL_NOISE);
            *s = ImuSample {
                gyro_rad_s: [g.x, g.y, g.z],
                accel_m_s2: [a.x, a.y, a.z],
                time_us,
            };
        }
        let mut link = [0u8; LINK_CAPACITY];
        let mut link_len = 0;
        let measured_us = now_us - POSE_LATENCY_US;
        let x = truth(measured_us);
        let p = x.position + self.noise.vector(POSE_NOISE);
        let [px, py, pz] = frames::flip_to_array(&p);
        let pose = ATT_POS_MOCAP_DATA {
            time_usec: measured_us,
            q: frames::quaternion_to_mavlink(&x.attitude),
            x: px,
            y: py,
            z: pz,
        };
        put(&pose, &mut self.sequence, &mut link, &mut link_len);
        if phase == Phase::Arm {
            // The explicit upside-down arm (param2 = 2989) and the helix mission.
            let arm = command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 1.0, 2989.0);
            put(&arm, &mut self.sequence, &mut link, &mut link_len);
            let start = command(MavCmd::MAV_CMD_MISSION_START, 0.0, 0.0);
            put(&start, &mut self.sequence, &mut link, &mut link_len);
        }
        Some(StepInputs {
            tick,
            now_us,
            phase,
            imu,
            link,
            link_len,
        })
    }
}

/// The flight pipeline of the paper vehicle, as the firmware boots it.
/// Panics if `FlightConfig::paper()` is refused (it is not; a test checks).
pub fn new_pipeline() -> FlightPipeline {
    match FlightPipeline::new(&FlightConfig::paper()) {
        Ok(p) => p,
        Err(_) => panic!("FlightConfig::paper() refused"),
    }
}

/// One full control step as the firmware's control task runs it: the tick's IMU samples, its
/// link bytes, then `control_tick`. Never inlined, so that every caller (MCU bench, host bench,
/// host comparison) runs the same code between its measurement brackets.
#[inline(never)]
pub fn full_step(pipeline: &mut FlightPipeline, inputs: &StepInputs) -> MotorOutput {
    for s in inputs.imu.iter() {
        pipeline.on_imu(s);
    }
    pipeline.on_link_bytes(&inputs.link[..inputs.link_len], inputs.now_us);
    pipeline.control_tick(inputs.now_us)
}

/// The compared figures of a full step (see [`FullOutputs`]), read after it.
pub fn full_outputs(pipeline: &FlightPipeline, out: &MotorOutput) -> FullOutputs {
    let (thrust, torque) = pipeline.last_mix().map_or((0.0, Vector3::zeros()), |m| {
        (m.achieved_thrust, m.achieved_torque)
    });
    [
        out.throttle[0],
        out.throttle[1],
        out.throttle[2],
        out.throttle[3],
        thrust,
        torque.x,
        torque.y,
        torque.z,
    ]
}

/// True when the last step ran the real flight path: armed, flying the helix, the controller
/// and the mixer ran (not an idle or failsafe early return).
pub fn on_flight_path(pipeline: &FlightPipeline) -> bool {
    let s = pipeline.status();
    s.state == FlightState::Armed
        && s.mode == crate::pipeline::Mode::Helix
        && pipeline.last_mix().is_some()
        && s.counters.non_finite == 0
}

/// The inputs of the `k`-th controller step (`k = 1..=FLIGHT_TICKS`): the scripted state
/// (exact, no estimator) and the helix reference at flight time `k · 10 ms`.
pub fn controller_inputs(k: u32) -> ControllerInputs {
    let x = truth(ARM_US + u64::from(k) * TICK_US);
    ControllerInputs {
        state: VehicleState {
            position: x.position,
            velocity: x.velocity,
            attitude: x.attitude,
            angular_velocity: x.angular_velocity,
        },
        reference: helix_reference(k as f32 * CONTROLLER_DT),
        dt: CONTROLLER_DT,
    }
}

/// The paper's controller (vehicle, Table I gains) for the helix, filters at zero.
/// Panics if the paper parameters are refused (they are not; a test checks).
pub fn new_controller() -> Controller<f32> {
    let c = FlightConfig::paper();
    let k = ReferenceTrajectory::<f32>::paper_helix().constants();
    match Controller::new(c.vehicle, c.gains, &k) {
        Ok(ctl) => ctl,
        Err(_) => panic!("paper controller refused"),
    }
}

/// One controller step (`Controller::step`), never inlined (see [`full_step`]).
/// Errors: [`StepError`] as `Controller::step`.
#[inline(never)]
pub fn controller_step(
    controller: &mut Controller<f32>,
    inputs: &ControllerInputs,
) -> Result<ControlOutput<f32>, StepError> {
    controller.step(&inputs.state, &inputs.reference, inputs.dt)
}

/// The compared figures of a controller step (see [`ControllerOutputs`]); NaN for an error.
pub fn controller_outputs(out: &Result<ControlOutput<f32>, StepError>) -> ControllerOutputs {
    match out {
        Ok(o) => [o.thrust, o.torque.x, o.torque.y, o.torque.z],
        Err(_) => [f32::NAN; 4],
    }
}

/// One comparable record of the sequence, as the MCU bench prints it and the host recomputes it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Record {
    /// The arming tick (tick number, outputs).
    Arm(u32, FullOutputs),
    /// A flight tick's full step (flight tick `1..=FLIGHT_TICKS`, outputs).
    Full(u32, FullOutputs),
    /// A controller step (flight tick, outputs).
    Controller(u32, ControllerOutputs),
}

/// Runs the whole sequence on this machine, calling `record` for every arming, full and
/// controller step, in the order the MCU bench brackets them (per flight tick: the full step,
/// then the controller step). Returns false if some flight step left the flight path
/// (see [`on_flight_path`]).
pub fn run_sequence(mut record: impl FnMut(Record)) -> bool {
    let mut pipeline = new_pipeline();
    let mut controller = new_controller();
    let mut ok = true;
    for inputs in StepSequence::new() {
        let out = full_step(&mut pipeline, &inputs);
        match inputs.phase {
            Phase::Setup => {}
            Phase::Arm => record(Record::Arm(inputs.tick, full_outputs(&pipeline, &out))),
            Phase::Flight => {
                let k = inputs.tick - ARM_TICK;
                ok &= on_flight_path(&pipeline);
                record(Record::Full(k, full_outputs(&pipeline, &out)));
                let c = controller_inputs(k);
                let r = controller_step(&mut controller, &c);
                record(Record::Controller(k, controller_outputs(&r)));
            }
        }
    }
    ok
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sequence calibrates, arms upside down into the helix, and every flight tick runs the
    /// controller and the mixer; every controller step succeeds; outputs are finite.
    #[test]
    fn sequence_exercises_the_flight_path() {
        let mut flights = 0;
        let mut controllers = 0;
        let ok = run_sequence(|r| match r {
            Record::Arm(_, o) => assert!(o.iter().all(|x| x.is_finite())),
            Record::Full(_, o) => {
                flights += 1;
                assert!(o.iter().all(|x| x.is_finite()));
                assert!(o[4] > 0.0, "thrust {o:?}");
            }
            Record::Controller(_, o) => {
                controllers += 1;
                assert!(o.iter().all(|x| x.is_finite()), "{o:?}");
            }
        });
        assert!(ok);
        assert_eq!(flights, FLIGHT_TICKS);
        assert_eq!(controllers, FLIGHT_TICKS);
    }

    /// The sequence is a pure function of nothing: two runs agree bit for bit.
    #[test]
    fn sequence_is_deterministic() {
        let a: Vec<_> = StepSequence::new().collect();
        let b: Vec<_> = StepSequence::new().collect();
        assert_eq!(a.len(), TOTAL_TICKS as usize);
        assert!(a.iter().zip(&b).all(|(x, y)| x == y));
    }

    /// The libm helix equals controller-core's paper helix up to rounding, and the scripted
    /// state starts where the paper starts (9.2 m from the helix, upside down).
    #[test]
    fn helix_and_truth_match_the_paper() {
        let h = ReferenceTrajectory::<f32>::paper_helix();
        for k in 0..300 {
            let t = k as f32 * 0.01;
            let (a, b) = (helix_reference(t), h.sample(t));
            assert!((a.position - b.position).norm() < 1e-5);
            assert!((a.snap - b.snap).norm() < 1e-5);
            assert!((a.heading_acceleration - b.heading_acceleration).norm() < 1e-4);
        }
        let x = truth(0);
        assert!(((x.position - helix_reference(0.0).position).norm() - 9.2).abs() < 0.05);
        assert!((x.attitude * Vector3::z()).z < -0.99);
        // At rest the accelerometer reads +g along inertial up.
        assert!((x.attitude * x.specific_force - Vector3::new(0.0, 0.0, GRAVITY)).norm() < 1e-4);
        // Continuity at the arming time.
        let y = truth(ARM_US + 1);
        assert!((y.position - x.position).norm() < 1e-4);
    }

    /// The body rates are consistent with the attitude: integrating them reproduces it.
    #[test]
    fn rates_match_attitude() {
        let mut q = truth(ARM_US).attitude;
        for i in 0..1000u64 {
            let t0 = ARM_US + i * 1000;
            let w = (truth(t0).angular_velocity + truth(t0 + 1000).angular_velocity) * 0.5;
            q *= UnitQuaternion::from_scaled_axis(w * 1e-3);
        }
        let end = truth(ARM_US + 1_000_000).attitude;
        assert!(q.angle_to(&end) < 2e-3, "{}", q.angle_to(&end));
    }
}
