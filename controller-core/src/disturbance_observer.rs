//! The velocity disturbance observer that anchors the integral action's estimate, so that large
//! transients (a flip, a start 10 m away, saturated feedback) cannot wind it up.
//!
//! Source: extension, docs/integral-action.md ("The observer"), not in the paper. The law's
//! model of the translational dynamics is `p̈ = (T/m) R e₃ − g e₃ + d` (eq:SystemDynamics with
//! a disturbance acceleration `d`, inertial). The observer keeps a velocity `v̂` [m/s] that follows
//! the model with the estimate `−η` in place of `d`, corrected by the measured velocity:
//!
//! * `v̂̇ = (T/m) R e₃ − g e₃ − η + L_v (v − v̂)`, propagated by one Euler step per sample with the
//!   sample's thrust `T` and measured attitude `R` (both held over the sample);
//! * the estimate's raw rate is `−k_i sat_z̄(z₁) − L_d (v − v̂)` before the rate and level clamps
//!   of [`crate::integral`]: the innovation `v − v̂` measures `d + η` directly, whatever the
//!   position error, and `z₁` (clamped to `±z̄` per axis) only trims what the observer leaves,
//!   such as the part of a mass error that moves with the reference's acceleration.
//!
//! The clamps still bound `|η_i| ≤ M_i,i` and `|η̇_i| ≤ R_i,i`, so the extended bounds of
//! [`crate::certify`] hold unchanged; only the local-stability conditions differ
//! ([`crate::integral_stability`]).

use nalgebra::Vector3;

use crate::parameter_error::{positive, ParameterError};
use crate::scalar::Scalar;

/// Gains of the disturbance observer (extension, docs/integral-action.md).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObserverGains<T: Scalar> {
    /// `L_v` [1/s]: gain of the velocity innovation `v − v̂` in the observer's velocity.
    pub velocity_gain: T,
    /// `L_d` [1/s²]: gain of the velocity innovation in the estimate's rate.
    pub disturbance_gain: T,
    /// `z̄` \[m\]: per-axis clamp of `z₁` before `k_i` multiplies it, so that a transient error
    /// drives the estimate at most at `k_i z̄`, which the innovation term outweighs.
    pub error_limit: T,
}

impl<T: Scalar> ObserverGains<T> {
    /// Checks `L_v, L_d, z̄ > 0` (finite). Errors: [`ParameterError::NotPositive`] naming the
    /// first offender (`"L_v"`, `"L_d"`, `"z_bar"`).
    pub fn validate(&self) -> Result<(), ParameterError> {
        positive("L_v", self.velocity_gain)?;
        positive("L_d", self.disturbance_gain)?;
        positive("z_bar", self.error_limit)
    }

    /// The estimate's raw rate [m/s³] before the clamps: `−k_i sat_z̄(z₁) − L_d (v − v̂)`, with
    /// `integral_gain = k_i` [1/s³], `z1` \[m\] and `innovation = v − v̂` [m/s], all inertial.
    pub fn raw_rate(
        &self,
        integral_gain: T,
        z1: &Vector3<T>,
        innovation: &Vector3<T>,
    ) -> Vector3<T> {
        let z1 = z1.map(|x| x.clamp(-self.error_limit, self.error_limit));
        z1 * (-integral_gain) - innovation * self.disturbance_gain
    }

    /// `v̂` [m/s] after a sample of `h` \[s\]: one Euler step of
    /// `v̂̇ = (T/m) R e₃ − g e₃ − η + L_v (v − v̂)`. `thrust` \[N\], `mass` \[kg\], `body_z = R e₃`,
    /// `gravity` [m/s²], `estimate = η` [m/s²]; vectors inertial.
    #[allow(clippy::too_many_arguments)]
    pub fn advance(
        &self,
        observed_velocity: &Vector3<T>,
        velocity: &Vector3<T>,
        thrust: T,
        mass: T,
        body_z: &Vector3<T>,
        gravity: T,
        estimate: &Vector3<T>,
        h: T,
    ) -> Vector3<T> {
        let modelled = body_z * (thrust / mass) - Vector3::z() * gravity - estimate;
        let correction = (velocity - observed_velocity) * self.velocity_gain;
        observed_velocity + (modelled + correction) * h
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn gains() -> ObserverGains<f64> {
        ObserverGains {
            velocity_gain: 4.0,
            disturbance_gain: 4.0,
            error_limit: 0.05,
        }
    }

    /// Given a point mass hovering under a constant disturbance `d` with the thrust exactly
    /// cancelling gravity, when the observer (with the rate and level clamps of the integral
    /// action, `k_i = 0`) runs for 10 s at 100 Hz, then the estimate is `−d` to 1e-6, whatever
    /// the initial velocity error; and the velocity the observer predicts matches the true one.
    #[test]
    fn a_constant_disturbance_is_estimated() {
        use crate::integral::{IntegralGains, IntegralState};
        let o = gains();
        let ig = IntegralGains {
            feedforward_scale: None,
            gain: 0.0,
            level: Vector3::repeat(3.0),
            rate: Vector3::repeat(10.0),
            bandwidth: 2.0,
            observer: Some(o),
        };
        let (m, g, h) = (0.5, 9.81, 0.01);
        let d = Vector3::new(0.3, -0.2, -1.5);
        let thrust = m * g;
        let mut v = Vector3::new(1.0, 0.0, -0.5);
        let mut v_hat = Vector3::zeros();
        let mut s = IntegralState::zero();
        for _ in 0..1000 {
            let innovation = v - v_hat;
            let rate = ig.clamped_rate(&s, &o.raw_rate(0.0, &Vector3::zeros(), &innovation), false);
            v_hat = o.advance(&v_hat, &v, thrust, m, &Vector3::z(), g, &s.estimate, h);
            s = ig.advance(&s, &rate, h);
            // The point mass: thrust cancels gravity, d accelerates it.
            v += d * h;
        }
        // v grew by d t; the observer tracked it and the estimate settled at −d.
        assert_relative_eq!(s.estimate, -d, epsilon = 1e-6);
        assert_relative_eq!(v_hat, v, epsilon = 1e-6);
    }

    /// `z₁` enters clamped to `±z̄`: a 100 m error drives the estimate no faster than 5 cm does.
    #[test]
    fn the_position_error_is_clamped() {
        let o = gains();
        let zero = Vector3::zeros();
        let far = o.raw_rate(2.0, &Vector3::new(100.0, -100.0, 0.01), &zero);
        assert_eq!(far, Vector3::new(-0.1, 0.1, -0.02));
    }
}
