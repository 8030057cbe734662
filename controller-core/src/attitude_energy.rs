//! The attitude energy and the bounds its sublevel sets put on the attitude error (extension,
//! docs/envelope-design.md): what the envelope design's local regime ([`crate::local_regime`])
//! switches on.
//!
//! With the law's exact feedforward `τ_c`, the attitude error obeys
//! `J ω̃̇ = Δ + τ_fb` with `ω̃ᵀΔ = 0` (the paper's `Δ`, Section V), whatever `ω_d` and `ω̇_d` are.
//! The energy `E = ½ ω̃ᵀJω̃ + Ψ(ϑ̃)`, with `Ψ(ϑ) = (M_ϑ/k_ϑ)(√(M_ϑ² + k_ϑ²|ϑ|²) − M_ϑ)` (whose
//! gradient is `s_ϑ(k_ϑ ϑ)`) and, with tilt priority, the trace potential `½ tr(G(I − R̃))`,
//! obeys `Ė = −ω̃ᵀ s_ω(ω̃) ≤ 0` along flows (the MRP identity `ϑᵀT(ϑ) = (1 + |ϑ|²)/4 ϑᵀ` turns the
//! MRP term into `d/dt Ψ`), and drops at the path lifting's jumps (`Ψ` falls as `|ϑ̃|` goes from
//! `1 + δ` to its shadow's `1/(1 + δ)`; the memory resets keep `ϑ̃`). So **every sublevel set
//! `{E ≤ c}` is forward invariant, whatever the position loop does**, as long as `ω_d` does not
//! jump (`ω̃` would).

use nalgebra::{Matrix3, Vector3};

use crate::attitude_control::AttitudeGains;
use crate::gains::Gains;
use crate::scalar::{lit, Scalar};
use crate::tilt_priority::TiltPriorityGains;

/// Bounds on the attitude error inside `{E ≤ c}`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnergyLimits<T: Scalar> {
    /// `c` \[J\].
    pub energy: T,
    /// Largest `|ϑ̃|` (dimensionless): `√((M_ϑ + c k_ϑ/M_ϑ)² − M_ϑ²)/k_ϑ`, from `Ψ(ϑ̃) ≤ c`,
    /// at most `1 + δ`.
    pub mrp: T,
    /// Largest rotation angle of `R̃` \[rad\]: `4 atan(|ϑ̃|)` (π once `|ϑ̃| ≥ 1`).
    pub angle: T,
    /// Largest `|ω̃_i|` per body axis [rad/s]: `√(2c/J_ii)`, from `½ ω̃ᵀJω̃ ≤ c`.
    pub omega_error: Vector3<T>,
}

/// The attitude energy `E = ½ ω̃ᵀJω̃ + Ψ(ϑ̃) (+ ½ tr(G(I − R̃)) + Ψ_t(ϑ̃) with tilt priority and its
/// turn-over term, docs/turn-over.md)` \[J\] of the
/// MRP error `mrp_error`, the angular velocity error `omega_error` [rad/s] (body) and the error
/// rotation `error_rotation` (`R̃ = R_dᵀR`) for the attitude law of `attitude` and
/// `tilt_priority` (a [`Gains`]' own, or the local regime's, [`crate::LocalAttitude`]) and the
/// inertia diagonal `inertia` [kg m²] (module documentation). Non-increasing along the closed
/// loop flying that law with the exact feedforward. No errors. Source: extension of Theorem 2's
/// argument (docs/envelope-design.md).
pub fn attitude_energy<T: Scalar>(
    attitude: &AttitudeGains<T>,
    tilt_priority: Option<&TiltPriorityGains<T>>,
    inertia: &Vector3<T>,
    mrp_error: &Vector3<T>,
    omega_error: &Vector3<T>,
    error_rotation: &Matrix3<T>,
) -> T {
    let (m, k) = (attitude.mrp_saturation, attitude.k_mrp);
    let kinetic = omega_error.dot(&inertia.component_mul(omega_error)) * lit(0.5);
    let potential = (m / k) * ((m * m + k * k * mrp_error.norm_squared()).sqrt() - m);
    let trace = match tilt_priority {
        None => T::zero(),
        Some(t) => {
            let g = &t.trace_weights;
            let r = error_rotation;
            (g.x * (T::one() - r[(0, 0)])
                + g.y * (T::one() - r[(1, 1)])
                + g.z * (T::one() - r[(2, 2)]))
                * lit(0.5)
                + t.turn_over.map_or(T::zero(), |o| o.potential(mrp_error))
        }
    };
    kinetic + potential + trace
}

/// The attitude error's bounds inside `{E ≤ energy}` for `gains` and `inertia` [kg m²] (module
/// documentation). The trace potential (tilt priority) only lowers them further; it is left
/// out, so they hold with or without it.
pub fn energy_limits<T: Scalar>(
    gains: &Gains<T>,
    inertia: &Vector3<T>,
    energy: T,
) -> EnergyLimits<T> {
    let a = &gains.attitude;
    let (m, k) = (a.mrp_saturation, a.k_mrp);
    let r = m + energy * k / m;
    let mrp = ((r * r - m * m).max(T::zero()).sqrt() / k).min(T::one() + gains.hysteresis);
    let angle = if mrp >= T::one() {
        T::pi()
    } else {
        lit::<T>(4.0) * mrp.atan()
    };
    EnergyLimits {
        energy,
        mrp,
        angle,
        omega_error: inertia.map(|j| (lit::<T>(2.0) * energy / j).sqrt()),
    }
}

#[cfg(test)]
pub(crate) mod tests;
