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

use crate::estimator::mul_increment;
use controller_core::scalar::{finite_probe, norm, normalize_quaternion};
#[cfg(test)]
use nalgebra::Quaternion;
use nalgebra::{UnitQuaternion, Vector3};

/// Mahony filter state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mahony {
    attitude: UnitQuaternion<f32>,
    integral: Vector3<f32>,
    kp: f32,
    ki: f32,
    gravity: f32,
    /// `0.2 g`, the accelerometer gate's half-width [m/s²], computed once.
    gate: f32,
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
            gate: 0.2 * gravity,
        }
    }

    /// The estimate, body FLU to NWU.
    pub fn attitude(&self) -> UnitQuaternion<f32> {
        self.attitude
    }

    /// Re-anchors on an external attitude (the fused mocap one); keeps the bias integral.
    pub fn anchor(&mut self, q: &UnitQuaternion<f32>) {
        // (One probe, finite iff every coordinate is, instead of four tests.)
        if finite_probe(0.0, &q.coords).is_finite() {
            self.attitude = *q;
        }
    }

    /// One update with bias-corrected gyro `gyro` [rad/s] and accelerometer `accel` [m/s²]
    /// (both body FLU) over `dt` \[s\]. Non-finite inputs or `dt` are ignored.
    pub fn update(&mut self, gyro: &Vector3<f32>, accel: &Vector3<f32>, dt: f32) {
        // (Two `all`s rather than a `chain`: the same test, a third of the instructions.)
        let finite = gyro.iter().all(|x| x.is_finite()) && accel.iter().all(|x| x.is_finite());
        if finite {
            self.update_finite(gyro, accel, dt);
        }
    }

    /// [`Mahony::update`] for a caller that has already refused non-finite samples (the
    /// pipeline, after the estimator's check): the same update without testing the six inputs
    /// again. A non-finite `dt` is still ignored, and so is an update whose result is not
    /// finite (a finite gyro reading so large that the rates overflow).
    pub fn update_finite(&mut self, gyro: &Vector3<f32>, accel: &Vector3<f32>, dt: f32) {
        // (Two float comparisons: NaN, ±∞ and dt ≤ 0 all fail them.)
        if !(dt > 0.0 && dt <= f32::MAX) {
            return;
        }
        self.step(gyro, accel, dt);
    }

    /// [`Mahony::update_finite`] for a time step that is never NaN or +∞ (the pipeline's: the
    /// IMU interval, finite, capped): only `dt > 0` is left to test, the same decision.
    pub(crate) fn update_finite_dt(&mut self, gyro: &Vector3<f32>, accel: &Vector3<f32>, dt: f32) {
        if dt > 0.0 {
            self.step(gyro, accel, dt);
        }
    }

    /// The update itself, `dt` positive and finite.
    #[inline(always)]
    fn step(&mut self, gyro: &Vector3<f32>, accel: &Vector3<f32>, dt: f32) {
        let mut w = *gyro;
        let n = norm(accel);
        // (No `n > 0` test: the gate implies it. It needs `0.2 g > |n − g| ≥ 0`, so g > 0,
        // and then n > 0.8 g; a NaN fails it.)
        if (n - self.gravity).abs() < self.gate {
            let a = accel / n;
            // v̂ = R̂ᵀ e₃, the third row of R̂ (fewer operations than rotating e₃).
            let q = self.attitude.as_ref();
            let (qw, qx, qy, qz) = (q.w, q.i, q.j, q.k);
            let up = Vector3::new(
                2.0 * (qx * qz - qw * qy),
                2.0 * (qy * qz + qw * qx),
                1.0 - 2.0 * (qx * qx + qy * qy),
            );
            let e = a.cross(&up);
            self.integral += e * (self.ki * dt);
            w += e * self.kp + self.integral;
        }
        let q = mul_increment(&self.attitude, &(w * (0.5 * dt)));
        // One probe (`Σ 0·x`, finite iff every coordinate is) instead of four tests.
        if finite_probe(0.0, &q.coords).is_finite() {
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

    /// The closed-form `R̂ᵀ e₃` agrees with nalgebra's rotation of `e₃` (through one update's
    /// correction term: with `k_I = 0`, `k_P = 1` and a zero gyro, the attitude moves by
    /// `½ dt (â × v̂)`), over a grid of attitudes.
    #[test]
    fn up_vector_matches_the_rotation() {
        for k in 0..200 {
            let a = k as f32 * 0.173;
            let q = UnitQuaternion::from_euler_angles(a, 0.7 * a - 1.0, 1.3 * a);
            let accel = Vector3::new(0.3, -0.2, 9.8);
            let mut m = Mahony::new(1.0, 0.0, 9.81);
            m.anchor(&q);
            m.update_finite(&Vector3::zeros(), &accel, 1e-3);
            let up = q.inverse_transform_vector(&Vector3::z());
            let e = (accel / norm(&accel)).cross(&up);
            let half = e * 0.5e-3;
            let want =
                normalize_quaternion(q.into_inner() * Quaternion::new(1.0, half.x, half.y, half.z));
            assert!((m.attitude().coords - want.coords).amax() < 1e-6, "{k}");
        }
    }

    /// A finite gyro reading so large that the update overflows leaves the attitude finite.
    #[test]
    fn overflowing_update_is_ignored() {
        let mut m = Mahony::new(2.0, 0.1, 9.81);
        m.update_finite(&Vector3::new(3e38, 3e38, 0.0), &Vector3::z(), 1e-3);
        m.update_finite(&Vector3::new(3e38, 0.0, 0.0), &Vector3::z(), f32::INFINITY);
        assert!(m.attitude().coords.iter().all(|x| x.is_finite()));
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
