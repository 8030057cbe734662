//! IMU-only attitude (Mahony's explicit complementary filter) kept running for the failsafe.
//!
//! `ω_c = ω + k_P e + k_I ∫e`, `e = â × v̂`, with `â` the measured specific-force direction
//! (body) and `v̂ = R̂ᵀ e₃` the estimated "up" direction in the body (an accelerometer at rest
//! reads `+g` along up); `q̇ = ½ q ⊗ (0, ω_c)`. Source: R. Mahony, T. Hamel, J.-M. Pflimlin,
//! "Nonlinear complementary filters on the special orthogonal group", IEEE TAC 2008.
//!
//! Written here rather than taken from the `ahrs` crate: its current release (0.8) depends on
//! nalgebra 0.34 while this workspace uses 0.35 (two nalgebra copies, incompatible types), and
//! the failsafe also needs to re-anchor the filter on the mocap attitude and to gate the
//! accelerometer, which its API does not expose.
//!
//! Frames: body FLU, inertial NWU (z up). Yaw is unobservable without a magnetometer: it
//! follows the gyro.

use controller_core::scalar::{norm, normalize_quaternion};
use nalgebra::{Quaternion, UnitQuaternion, Vector3};

/// Mahony filter state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mahony {
    attitude: UnitQuaternion<f32>,
    integral: Vector3<f32>,
    kp: f32,
    ki: f32,
    gravity: f32,
}

impl Mahony {
    /// Starts level with gains `kp` [1/s] and `ki` [1/s²]; `gravity` [m/s²] gates the
    /// accelerometer (used only while `| |a| − g | < 0.2 g`).
    pub fn new(kp: f32, ki: f32, gravity: f32) -> Self {
        Self {
            attitude: UnitQuaternion::identity(),
            integral: Vector3::zeros(),
            kp,
            ki,
            gravity,
        }
    }

    /// The estimate, body FLU to NWU.
    pub fn attitude(&self) -> UnitQuaternion<f32> {
        self.attitude
    }

    /// Re-anchors on an external attitude (the fused mocap one); keeps the bias integral.
    pub fn anchor(&mut self, q: &UnitQuaternion<f32>) {
        if q.coords.iter().all(|x| x.is_finite()) {
            self.attitude = *q;
        }
    }

    /// One update with bias-corrected gyro `gyro` [rad/s] and accelerometer `accel` [m/s²]
    /// (both body FLU) over `dt` \[s\]. Non-finite inputs or `dt` are ignored.
    pub fn update(&mut self, gyro: &Vector3<f32>, accel: &Vector3<f32>, dt: f32) {
        // (Two `all`s rather than a `chain`: the same test, a third of the instructions.)
        let finite = gyro.iter().all(|x| x.is_finite()) && accel.iter().all(|x| x.is_finite());
        if !(dt.is_finite() && dt > 0.0 && finite) {
            return;
        }
        let mut w = *gyro;
        let n = norm(accel);
        if (n - self.gravity).abs() < 0.2 * self.gravity && n > 0.0 {
            let a = accel / n;
            let up = self.attitude.inverse_transform_vector(&Vector3::z());
            let e = a.cross(&up);
            self.integral += e * (self.ki * dt);
            w += e * self.kp + self.integral;
        }
        let half = w * (0.5 * dt);
        let dq = Quaternion::new(1.0, half.x, half.y, half.z);
        let q = self.attitude.into_inner() * dq;
        if q.coords.iter().all(|x| x.is_finite()) {
            self.attitude = normalize_quaternion(q);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Started 30° off in roll at rest, the estimate converges to level (accelerometer reads
    /// +g up); with a constant yaw rate it integrates the yaw.
    #[test]
    fn converges_to_level_and_integrates_yaw() {
        // k_I = k_P²/4: the error dynamics are critically damped (double pole at −k_P/2).
        let mut m = Mahony::new(2.0, 1.0, 9.81);
        m.anchor(&UnitQuaternion::from_euler_angles(
            core::f32::consts::FRAC_PI_6,
            0.0,
            0.0,
        ));
        for _ in 0..12_000 {
            // True attitude level: specific force (0, 0, g) in the body.
            m.update(&Vector3::zeros(), &Vector3::new(0.0, 0.0, 9.81), 1e-3);
        }
        let (r, p, _) = m.attitude().euler_angles();
        assert!(r.abs() < 1e-3 && p.abs() < 1e-3, "{r} {p}");
        let mut m = Mahony::new(2.0, 0.1, 9.81);
        for _ in 0..1000 {
            m.update(
                &Vector3::new(0.0, 0.0, 0.5),
                &Vector3::new(0.0, 0.0, 9.81),
                1e-3,
            );
        }
        let (_, _, y) = m.attitude().euler_angles();
        assert!((y - 0.5).abs() < 1e-3, "{y}");
    }

    /// NaN input leaves the estimate untouched.
    #[test]
    fn ignores_non_finite() {
        let mut m = Mahony::new(2.0, 0.1, 9.81);
        m.update(&Vector3::new(f32::NAN, 0.0, 0.0), &Vector3::z(), 1e-3);
        m.update(&Vector3::zeros(), &Vector3::z(), f32::NAN);
        assert_eq!(m.attitude(), UnitQuaternion::identity());
    }
}
