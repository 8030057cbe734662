//! The failsafe law: IMU-only level hold and a slow descent, for when the pose is lost or a
//! value went non-finite. The attitude part is the paper's saturated attitude law
//! ([`AttitudeGains::evaluate`], eq. of the torque `τ`) towards level at the current yaw with
//! `ω_d = 0`, on the MRP of the attitude error ([`mrp_from_quaternion`]); the thrust tracks a
//! descent speed on the dead-reckoned vertical velocity.

use controller_core::attitude_control::AttitudeGains;
use controller_core::mrp::{mrp_from_quaternion, rotation_from_quaternion};
use nalgebra::{UnitQuaternion, Vector3};

use super::{FlightPipeline, MotorOutput};
use crate::config::FlightConfig;

/// One output of the failsafe law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct LevelHold {
    /// Collective thrust \[N\].
    pub thrust: f32,
    /// Torque [N m], body FLU.
    pub torque: Vector3<f32>,
}

impl LevelHold {
    /// The law at the IMU-only attitude `q` (body to inertial NWU), body rate `omega` [rad/s]
    /// (FLU) and dead-reckoned vertical velocity `vz` [m/s] (z up):
    ///
    /// - torque: the saturated attitude law on `ϑ = φ(q_e)`, `q_e = q_d⁻¹ q` with `q_d` level
    ///   at `q`'s yaw, `q_e` taken with `q₀ ≥ 0` (the short way round), `ω_d = 0`, `ω̇_d = 0`;
    /// - thrust: `T = m (g + k (−v_descent − v_z)) / max(e₃ᵀ R e₃, c_min)`, kept in
    ///   `[lo, hi] · m g` ([`crate::config::SafetyConfig`]: `failsafe_descent_gain` `k`,
    ///   `failsafe_tilt_cos_min` `c_min`, `failsafe_thrust_ratio`).
    ///
    /// Non-finite inputs give non-finite outputs: see [`LevelHold::is_finite`].
    #[inline]
    pub fn law(cfg: &FlightConfig, q: &UnitQuaternion<f32>, omega: &Vector3<f32>, vz: f32) -> Self {
        let c = cfg;
        let (_, _, yaw) = q.euler_angles();
        let q_d = UnitQuaternion::from_euler_angles(0.0, 0.0, yaw);
        let mut q_e = (q_d.inverse() * q).into_inner();
        if q_e.w < 0.0 {
            q_e = -q_e;
        }
        // With q₀ ≥ 0 the MRP is finite (|ϑ| ≤ 1); a NaN q₀ gives a NaN ϑ, not `None`, and a
        // `None` could only come from q₀ = −1: both go to the non-finite fallback.
        let mrp = mrp_from_quaternion(&q_e).unwrap_or_else(|| Vector3::repeat(f32::NAN));
        let r_e = rotation_from_quaternion(&q_e);
        let gains: &AttitudeGains<f32> = &c.gains.attitude;
        let torque = gains
            .evaluate(
                &mrp,
                omega,
                &r_e,
                &Vector3::zeros(),
                &Vector3::zeros(),
                &c.vehicle.inertia,
            )
            .torque;
        let (m, g) = (c.vehicle.mass, c.vehicle.gravity);
        let s = &c.safety;
        let up = (q * Vector3::z()).z.max(s.failsafe_tilt_cos_min);
        let accel = g + s.failsafe_descent_gain * (-s.failsafe_descent_speed - vz);
        let [lo, hi] = s.failsafe_thrust_ratio;
        let thrust = (m * accel / up).max(lo * m * g).min(hi * m * g);
        Self { thrust, torque }
    }

    /// Whether thrust and torque are finite (what may reach the mixer).
    pub fn is_finite(&self) -> bool {
        self.thrust.is_finite() && self.torque.iter().all(|x| x.is_finite())
    }

    /// What flies when the law is not finite: the lowest failsafe thrust `lo · m g`, no torque.
    pub fn fallback(cfg: &FlightConfig) -> Self {
        let (m, g) = (cfg.vehicle.mass, cfg.vehicle.gravity);
        let [lo, _] = cfg.safety.failsafe_thrust_ratio;
        Self {
            thrust: lo * m * g,
            torque: Vector3::zeros(),
        }
    }
}

impl FlightPipeline {
    /// The failsafe's motor output: [`LevelHold::law`] on the Mahony attitude and the
    /// estimator's rate and vertical velocity, its fallback (counted as non-finite) if the
    /// law is not finite, through the mixer. Keeps the thrust for the landed detector.
    pub(super) fn failsafe_output(&mut self) -> MotorOutput {
        let q = self.mahony.attitude();
        let omega = self.estimator.angular_velocity();
        let vz = self.estimator.vertical_velocity();
        let mut hold = LevelHold::law(&self.cfg, &q, &omega, vz);
        if !hold.is_finite() {
            self.non_finite("failsafe");
            hold = LevelHold::fallback(&self.cfg);
        }
        self.failsafe_thrust = hold.thrust;
        self.mix_to_output(hold.thrust, &hold.torque)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cfg() -> FlightConfig {
        FlightConfig::paper()
    }

    fn weight() -> f32 {
        let v = cfg().vehicle;
        v.mass * v.gravity
    }

    #[test]
    fn given_level_and_descending_at_the_set_speed_when_law_runs_then_weight_and_no_torque() {
        let c = cfg();
        let q = UnitQuaternion::from_euler_angles(0.0, 0.0, 1.2);
        let h = LevelHold::law(&c, &q, &Vector3::zeros(), -c.safety.failsafe_descent_speed);
        assert!(
            (h.thrust - weight()).abs() < 1e-5 * weight(),
            "{}",
            h.thrust
        );
        assert!(h.torque.norm() < 1e-6, "yaw is kept: {:?}", h.torque);
    }

    #[test]
    fn given_rolled_right_when_law_runs_then_torque_rolls_back_left() {
        let c = cfg();
        // Positive roll about body x (FLU): the law answers with a negative x torque.
        let q = UnitQuaternion::from_euler_angles(0.3, 0.0, -2.0);
        let h = LevelHold::law(&c, &q, &Vector3::zeros(), 0.0);
        assert!(h.torque.x < 0.0, "{:?}", h.torque);
        assert!(h.torque.y.abs() < 1e-3 * h.torque.x.abs());
    }

    #[test]
    fn given_falling_or_climbing_fast_when_law_runs_then_thrust_is_clamped() {
        let c = cfg();
        let [lo, hi] = c.safety.failsafe_thrust_ratio;
        let q = UnitQuaternion::identity();
        let falling = LevelHold::law(&c, &q, &Vector3::zeros(), -50.0);
        assert_eq!(falling.thrust, hi * c.vehicle.mass * c.vehicle.gravity);
        let climbing = LevelHold::law(&c, &q, &Vector3::zeros(), 50.0);
        assert_eq!(climbing.thrust, lo * c.vehicle.mass * c.vehicle.gravity);
    }

    #[test]
    fn given_tilted_past_the_cosine_floor_when_law_runs_then_thrust_divides_by_the_floor() {
        let mut c = cfg();
        // Widen the clamp so the tilt division shows.
        c.safety.failsafe_thrust_ratio = [0.0, 10.0];
        let v = -c.safety.failsafe_descent_speed;
        let level = LevelHold::law(&c, &UnitQuaternion::identity(), &Vector3::zeros(), v);
        let upside_down = UnitQuaternion::from_euler_angles(3.0, 0.0, 0.0);
        let tilted = LevelHold::law(&c, &upside_down, &Vector3::zeros(), v);
        let ratio = tilted.thrust / level.thrust;
        assert!(
            (ratio - 1.0 / c.safety.failsafe_tilt_cos_min).abs() < 1e-5,
            "{ratio}"
        );
    }

    #[test]
    fn given_a_nan_attitude_when_law_runs_then_not_finite_and_fallback_is_the_lowest_thrust() {
        let c = cfg();
        let nan = UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(f32::NAN, 0.0, 0.0, 0.0));
        assert!(!LevelHold::law(&c, &nan, &Vector3::zeros(), 0.0).is_finite());
        let f = LevelHold::fallback(&c);
        assert!(f.is_finite());
        assert_eq!(f.torque, Vector3::zeros());
        assert_eq!(f.thrust, c.safety.failsafe_thrust_ratio[0] * weight());
    }
}
