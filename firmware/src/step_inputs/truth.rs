//! The scripted trajectory of the bench sequence: the paper's helix computed with `libm`, and
//! the vehicle's state along the sequence (at rest upside down, then righting itself onto the
//! helix). Frames: inertial NWU, body FLU; SI units.

use controller_core::ReferenceSample;
use nalgebra::{Quaternion, UnitQuaternion, Vector2, Vector3};

use super::scenario::{REST_POSITION, REST_ROLL, REST_YAW};
use super::ARM_US;

/// Time to right the vehicle \[s\], roll wobble amplitude \[rad\] and angular frequency [rad/s].
const RIGHTING_S: f32 = 0.8;
const WOBBLE: f32 = 0.05;
const WOBBLE_RATE: f32 = 5.0;
/// Decay times of the position error and of the yaw error \[s\].
const POSITION_DECAY_S: f32 = 1.0;
const YAW_DECAY_S: f32 = 0.5;
/// Gravity [m/s²] (the paper vehicle's).
const GRAVITY: f32 = 9.81;
/// Helix angular frequency `f = 2π/15` [rad/s] (rounded from f64 like controller-core's).
const HELIX_RATE: f32 = (2.0 * core::f64::consts::PI / 15.0) as f32;

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

#[cfg(test)]
mod tests {
    use super::*;
    use controller_core::{ReferenceTrajectory, Trajectory};

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
