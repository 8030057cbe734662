//! The saturated MRP torque law with feedforward of Section V.
//!
//! `τ = −(1 + |ϑ̃|²)/4 · s_ϑ(k_ϑ ϑ̃) − s_ω(k_ω ω̃) − τ_c`, with radial saturations of levels
//! `M_ϑ`, `M_ω`, the angular velocity error `ω̃ = ω − R̃ᵀω_d` and the feedforward
//! `τ_c = [J R̃ᵀω_d]ₓ R̃ᵀω_d − J R̃ᵀω̇_d`. With `|ϑ̃| ≤ 1 + δ` each torque component is bounded
//! by `ι + J_ii U_ω̇d + ½|J_jj − J_kk| U_ωd²` (Theorem 2).

use nalgebra::{Matrix3, Vector3};

use crate::saturation::radial_saturation;
use crate::scalar::{lit, Scalar};

/// Gains of the attitude loop (Table I names in brackets).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AttitudeGains<T: Scalar> {
    /// `k_ϑ` [N m]: proportional gain on the MRP error, applied before the saturation.
    pub k_mrp: T,
    /// `k_ω` [N m s/rad]: gain on the angular velocity error, applied before the saturation.
    pub k_omega: T,
    /// `M_ϑ` [N m]: level of the radial saturation `s_ϑ`.
    pub mrp_saturation: T,
    /// `M_ω` [N m]: level of the radial saturation `s_ω`.
    pub omega_saturation: T,
}

/// The torque law's output and its parts, all in the body frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TorqueOutput<T: Scalar> {
    /// Commanded torque `τ` [N m].
    pub torque: Vector3<T>,
    /// `s_ϑ(k_ϑ ϑ̃)` [N m], `|·| < M_ϑ`.
    pub s_mrp: Vector3<T>,
    /// `s_ω(k_ω ω̃)` [N m], `|·| < M_ω`.
    pub s_omega: Vector3<T>,
    /// Feedforward `τ_c` [N m].
    pub feedforward: Vector3<T>,
    /// Angular velocity error `ω̃ = ω − R̃ᵀω_d` [rad/s].
    pub omega_error: Vector3<T>,
}

impl<T: Scalar> AttitudeGains<T> {
    /// Evaluates the torque law.
    ///
    /// Inputs: MRP error `ϑ̃` (dimensionless, from the path lifting), measured body angular
    /// velocity `ω` [rad/s], `R̃ = R_dᵀR`, `ω_d` [rad/s] and `ω̇_d` [rad/s²] in the desired body
    /// frame, and the inertia diagonal `(J₁₁, J₂₂, J₃₃)` [kg m²].
    /// Source: Section V, torque law `τ(x̃_ϑ)`, `s_ϑ`, `s_ω`, `τ_c`.
    pub fn evaluate(
        &self,
        mrp_error: &Vector3<T>,
        angular_velocity: &Vector3<T>,
        error_rotation: &Matrix3<T>,
        desired_angular_velocity: &Vector3<T>,
        desired_angular_acceleration: &Vector3<T>,
        inertia: &Vector3<T>,
    ) -> TorqueOutput<T> {
        let (omega_error, feedforward) = error_and_feedforward(
            angular_velocity,
            error_rotation,
            desired_angular_velocity,
            desired_angular_acceleration,
            inertia,
        );
        let (s_mrp, shape) = self.radial_mrp_term(mrp_error);
        let s_omega = radial_saturation(&(omega_error * self.k_omega), self.omega_saturation);
        TorqueOutput {
            torque: -s_mrp * shape - s_omega - feedforward,
            s_mrp,
            s_omega,
            feedforward,
            omega_error,
        }
    }
}

impl<T: Scalar> AttitudeGains<T> {
    /// The radial MRP term's parts: `s_ϑ(k_ϑ ϑ̃)` [N m] and the shape `(1 + |ϑ̃|²)/4`, whose
    /// product is the term (Section V).
    #[inline]
    pub(crate) fn radial_mrp_term(&self, mrp_error: &Vector3<T>) -> (Vector3<T>, T) {
        let s_mrp = radial_saturation(&(mrp_error * self.k_mrp), self.mrp_saturation);
        let shape = (T::one() + mrp_error.norm_squared()) * lit::<T>(0.25);
        (s_mrp, shape)
    }
}

/// `ω̃ = ω − R̃ᵀω_d` [rad/s] and the feedforward `τ_c = [J R̃ᵀω_d]ₓ R̃ᵀω_d − J R̃ᵀω̇_d` [N m],
/// body frame (Section V); inputs as [`AttitudeGains::evaluate`].
#[inline]
pub(crate) fn error_and_feedforward<T: Scalar>(
    angular_velocity: &Vector3<T>,
    error_rotation: &Matrix3<T>,
    desired_angular_velocity: &Vector3<T>,
    desired_angular_acceleration: &Vector3<T>,
    inertia: &Vector3<T>,
) -> (Vector3<T>, Vector3<T>) {
    let rt = error_rotation.transpose();
    let w_d = rt * desired_angular_velocity;
    let w_d_dot = rt * desired_angular_acceleration;
    let omega_error = angular_velocity - w_d;
    let feedforward = inertia.component_mul(&w_d).cross(&w_d) - inertia.component_mul(&w_d_dot);
    (omega_error, feedforward)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn gains() -> AttitudeGains<f64> {
        AttitudeGains {
            k_mrp: 100.0,
            k_omega: 0.1,
            mrp_saturation: 0.206,
            omega_saturation: 0.045,
        }
    }

    /// With ω_d = ω̇_d = 0 the torque is the saturated PD alone and bounded by ι per component.
    #[test]
    fn feedback_alone_is_bounded_by_iota() {
        let g = gains();
        let j = Vector3::new(2.24e-3, 2.9e-3, 5.3e-3);
        let iota = (1.0 + 1.02f64.powi(2)) * 0.206 / 4.0 + 0.045;
        for k in 0..1000 {
            let a = k as f64 * 0.37;
            let mrp = Vector3::new(a.sin(), (1.3 * a).cos(), (0.7 * a).sin()).normalize() * 1.02;
            let w = Vector3::new((2.1 * a).cos(), a.sin(), (0.3 * a).cos()) * 50.0;
            let out = g.evaluate(
                &mrp,
                &w,
                &Matrix3::identity(),
                &Vector3::zeros(),
                &Vector3::zeros(),
                &j,
            );
            assert!(out.torque.amax() <= iota, "{} > {iota}", out.torque.amax());
            assert!(out.s_mrp.norm() < 0.206 && out.s_omega.norm() < 0.045);
        }
    }

    /// At zero error the torque is exactly what the rigid body needs to follow ω_d, ω̇_d:
    /// Jω̇_d = (Jω_d) × ω_d + τ  ⇔  τ = −τ_c.
    #[test]
    fn zero_error_gives_the_feedforward_torque() {
        let g = gains();
        let j = Vector3::new(2.24e-3, 2.9e-3, 5.3e-3);
        let wd = Vector3::new(0.3, -1.2, 2.0);
        let wdd = Vector3::new(4.0, 1.0, -3.0);
        let out = g.evaluate(&Vector3::zeros(), &wd, &Matrix3::identity(), &wd, &wdd, &j);
        let needed = j.component_mul(&wdd) - j.component_mul(&wd).cross(&wd);
        assert_relative_eq!(out.torque, needed, epsilon = 1e-15);
        assert_relative_eq!(out.omega_error, Vector3::zeros(), epsilon = 1e-15);
    }
}
