//! Per-axis attitude feedback with tilt priority (an extension; docs/tilt-priority.md).
//!
//! The paper's feedback `−(1 + |ϑ̃|²)/4 · s_ϑ(k_ϑ ϑ̃) − s_ω(k_ω ω̃)` is radial: every axis gets
//! the same level `ι`, so the weakest axis (yaw, on a real propeller about a tenth of roll's
//! authority) caps roll and pitch too. This law keeps the paper's radial MRP term (small: it
//! only has to break the symmetry at the half turn) and adds
//! - the body-frame gradient of the weighted trace potential `½ tr(G(I − R̃))`,
//!   `τ_trace = −½ vee(G R̃ − R̃ᵀ G)`, `G = diag(g₁, g₂, g₃)` [N m], whose component `i` is
//!   bounded by `½(g_j + g_k)`: with `g₃` large and `g₁ = g₂` small, roll and pitch get the
//!   level `½(g₁ + g₃)` and yaw only `g₁`, and the tilt part `g₃(1 − e₃ᵀR̃e₃)/2` of the
//!   potential has no yaw component at all, so the body z axis turns to the desired thrust
//!   direction first (the shortest tilt), the heading after;
//! - per-axis damping `s_ω,i = M_ω,i k_ω,i ω̃_i / √(M_ω,i² + (k_ω,i ω̃_i)²)`.
//!
//! `τ = −(1 + |ϑ̃|²)/4 · s_ϑ(k_ϑ ϑ̃) − ½ vee(G R̃ − R̃ᵀ G) − s_ω(ω̃) − τ_c`, with the paper's
//! feedforward `τ_c`. Per-axis bound of the feedback: `ι_i = (1 + (1+δ)²) M_ϑ/4 + ½(g_j + g_k)
//! + M_ω,i`, so Theorem 2's condition becomes per axis with `ι_i` in place of `ι`.
//!
//! Stability (docs/tilt-priority.md): `V = ½ ω̃ᵀJω̃ + Ψ_MRP(ϑ̃) + ½ tr(G(I − R̃))` with
//! `Ψ_MRP = (M_ϑ/k_ϑ)(√(M_ϑ² + k_ϑ²|ϑ̃|²) − M_ϑ)` gives `V̇ = −ω̃ᵀ s_ω(ω̃) ≤ 0` on flows (the
//! paper's identity `ϑᵀT(ϑ) = (1 + |ϑ|²)/4 ϑᵀ` for the radial term, `d/dt ½tr(G(I − R̃)) =
//! ½ ω̃ᵀ vee(GR̃ − R̃ᵀG)` for the trace term) and a strict decrease at the MRP switch (the trace
//! term is a function of `R̃`, unchanged by the jump). The only point of the flow set where the
//! feedback vanishes at `ω̃ = 0` is `ϑ̃ = 0` if the radial term outweighs the trace potential's
//! descent in the hysteresis band `1 ≤ |ϑ̃| ≤ 1 + δ` (beyond the half turn the trace potential
//! decreases along the ray): [`TiltPriorityGains::hysteresis_band`], a certificate condition.

use nalgebra::{Matrix3, Vector3};

use crate::attitude_control::{error_and_feedforward, AttitudeGains, TorqueOutput};
use crate::parameter_error::{positive, ParameterError};
use crate::scalar::{lit, to_f64, Scalar};
use crate::turn_over::TurnOver;

/// Gains of the tilt-priority feedback (extension, docs/tilt-priority.md). The radial MRP
/// term keeps the paper's `k_ϑ`, `M_ϑ` ([`AttitudeGains`]); these replace the radial damping
/// `s_ω(k_ω ω̃)` (the paper's `k_ω`, `M_ω` are not used while this is on) and add the trace term.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TiltPriorityGains<T: Scalar> {
    /// Weights `(g₁, g₂, g₃)` [N m] of the trace potential `½ tr(G(I − R̃))`, body axes; each
    /// `≥ 0`. Axis `i`'s trace torque is bounded by (and its stiffness at `R̃ = I` is)
    /// `½(g_j + g_k)` [N m, N m/rad].
    pub trace_weights: Vector3<T>,
    /// Per-axis damping gains `k_ω,i` [N m s/rad], body axes, `> 0`.
    pub omega_gains: Vector3<T>,
    /// Per-axis damping levels `M_ω,i` [N m], body axes, `> 0`.
    pub omega_levels: Vector3<T>,
    /// The turn-over term (docs/turn-over.md): a tilt-only push near the half turn, where the
    /// trace term has no gradient. `None`: off (the law as before, bit for bit).
    pub turn_over: Option<TurnOver<T>>,
}

impl<T: Scalar> TiltPriorityGains<T> {
    /// Checks `g_i ≥ 0` and `k_ω,i, M_ω,i > 0`, all finite.
    /// Errors: [`ParameterError::NotPositive`] naming the first offender (`"g_1"` for a
    /// negative or non-finite weight, `"k_omega_1"`, `"M_omega_1"`, ...).
    pub fn validate(&self) -> Result<(), ParameterError> {
        for (i, g) in self.trace_weights.iter().enumerate() {
            if !(g.is_finite() && *g >= T::zero()) {
                return Err(ParameterError::NotPositive {
                    name: ["g_1", "g_2", "g_3"][i],
                    value: to_f64(*g),
                });
            }
        }
        for (names, v) in [
            (["k_omega_1", "k_omega_2", "k_omega_3"], &self.omega_gains),
            (["M_omega_1", "M_omega_2", "M_omega_3"], &self.omega_levels),
        ] {
            for (name, x) in names.iter().zip(v.iter()) {
                positive(name, *x)?;
            }
        }
        if let Some(t) = &self.turn_over {
            t.validate()?;
        }
        Ok(())
    }

    /// `τ_trace = −½ vee(G R̃ − R̃ᵀ G)` [N m], body frame: the body-frame gradient of
    /// `½ tr(G(I − R̃))` with a minus sign. `R̃ = R_dᵀR` (3×3, on SO(3)).
    /// Source: extension (docs/tilt-priority.md); the weighted trace potential is that of
    /// Chaturvedi, Sanyal and McClamroch, "Rigid-body attitude control", IEEE CSM 2011.
    pub fn trace_torque(&self, error_rotation: &Matrix3<T>) -> Vector3<T> {
        let g = &self.trace_weights;
        let r = error_rotation;
        let half = lit::<T>(0.5);
        -Vector3::new(
            g.z * r[(2, 1)] - g.y * r[(1, 2)],
            g.x * r[(0, 2)] - g.z * r[(2, 0)],
            g.y * r[(1, 0)] - g.x * r[(0, 1)],
        ) * half
    }

    /// Per-axis damping `s_ω,i = M_ω,i k_ω,i ω̃_i / √(M_ω,i² + (k_ω,i ω̃_i)²)` [N m], body
    /// frame; `|s_ω,i| < M_ω,i` and `ω̃ᵀ s_ω > 0` for `ω̃ ≠ 0`. Input `ω̃` [rad/s].
    pub fn damping(&self, omega_error: &Vector3<T>) -> Vector3<T> {
        Vector3::from_fn(|i, _| {
            let (m, x) = (self.omega_levels[i], self.omega_gains[i] * omega_error[i]);
            m * x / (m * m + x * x).sqrt_ieee()
        })
    }

    /// `ι_i = (1 + (1+δ)²) M_ϑ/4 + ½(g_j + g_k) + M_ω,i (+ the turn-over term's bound)` [N m]:
    /// the per-axis bound of the feedback while `|ϑ̃| ≤ 1 + δ` (the triangle inequality over
    /// the terms). Inputs: the radial term's level `M_ϑ` [N m] and the hysteresis `δ`.
    /// Source: extension of Theorem 2's `ι` (docs/tilt-priority.md, docs/turn-over.md).
    pub fn feedback_levels(&self, mrp_saturation: T, hysteresis: T) -> Vector3<T> {
        let a = T::one() + hysteresis;
        let radial = (T::one() + a * a) * mrp_saturation * lit(0.25);
        let g = &self.trace_weights;
        let half = lit::<T>(0.5);
        Vector3::new((g.y + g.z) * half, (g.z + g.x) * half, (g.x + g.y) * half)
            + self.omega_levels.add_scalar(radial)
            + self.turn_over_bounds(hysteresis)
    }

    /// The turn-over term's per-axis bounds [N m] while `|ϑ̃| ≤ 1 + δ` (zero when it is off):
    /// [`TurnOver::bounds`]. Source: extension (docs/turn-over.md).
    pub fn turn_over_bounds(&self, hysteresis: T) -> Vector3<T> {
        self.turn_over
            .map_or(Vector3::zeros(), |t| t.bounds(hysteresis))
    }

    /// The hysteresis-band condition `(lhs, rhs)`, holding when `lhs > rhs`:
    /// `lhs = M_ϑ k_ϑ/√(M_ϑ² + k_ϑ²)`, the radial term's slope `|s_ϑ(k_ϑ ϑ̃)|` at `|ϑ̃| = 1`
    /// (it grows with `|ϑ̃|`), and `rhs = (tr G − min g)(t² − 1)t` with `t = 1 + δ`, which bounds
    /// the trace potential's descent rate `8(tr G − nᵀGn)(r² − 1)r/(1 + r²)³` along any ray
    /// `ϑ̃ = r n` with `1 ≤ r ≤ t`. When it holds, `V` increases along every ray of the flow set,
    /// so `ϑ̃ = 0` is the feedback's only zero there (no spurious equilibrium in the band).
    /// Source: extension (docs/tilt-priority.md).
    pub fn hysteresis_band(&self, attitude: &AttitudeGains<T>, hysteresis: T) -> (T, T) {
        let (m, k) = (attitude.mrp_saturation, attitude.k_mrp);
        let lhs = m * k / (m * m + k * k).sqrt_ieee();
        let g = &self.trace_weights;
        let t = T::one() + hysteresis;
        let rhs = (g.x + g.y + g.z - g.min()) * (t * t - T::one()) * t;
        (lhs, rhs)
    }

    /// Evaluates the whole torque law with this feedback; inputs and output as
    /// [`AttitudeGains::evaluate`] (whose `k_ϑ`, `M_ϑ` give the radial MRP term). In the output,
    /// `s_mrp` is `s_ϑ(k_ϑ ϑ̃)` and `s_omega` the per-axis damping.
    /// Source: extension (docs/tilt-priority.md); feedforward `τ_c` of Section V.
    #[allow(clippy::too_many_arguments)]
    pub fn evaluate(
        &self,
        attitude: &AttitudeGains<T>,
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
        let (s_mrp, shape) = attitude.radial_mrp_term(mrp_error);
        let s_omega = self.damping(&omega_error);
        let mut torque = -s_mrp * shape + self.trace_torque(error_rotation) - s_omega - feedforward;
        if let Some(t) = &self.turn_over {
            torque += t.torque(mrp_error);
        }
        TorqueOutput {
            torque,
            s_mrp,
            s_omega,
            feedforward,
            omega_error,
        }
    }
}

#[cfg(test)]
mod tests;
