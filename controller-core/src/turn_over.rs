//! The turn-over term: a tilt-only MRP potential that pushes roll and pitch hard near the half
//! turn, where the trace potential of tilt priority has no gradient (an extension;
//! docs/turn-over.md).
//!
//! **Why.** At a half turn about a horizontal axis (upside down) the trace term
//! `−½ vee(G R̃ − R̃ᵀG)` vanishes (`R̃` is symmetric and commutes with `G = diag(g₁, g₁, g₃)`),
//! and the only torque is the paper's radial MRP term, `(1 + |ϑ̃|²)/4 · M_ϑ`. That term is a
//! ball, as large about yaw as about roll, so its level is capped by the yaw authority (on the
//! x500, 0.267 N m of yaw against 2.9 N m of roll): the vehicle leaves the half turn at about
//! 1 rad/s² and falls while it does.
//!
//! **The potential.** With `ρ² = ϑ₁² + ϑ₂²` (the lifted MRP's horizontal part),
//! `Ψ_t(ϑ) = 2 M_t F(ρ²)`, `F' = b/2`, `b(s) = clamp((s − ρ₀²)/(1 − ρ₀²), 0, 1)`: zero below the
//! onset `ρ₀` (rotations by less than `4 atan ρ₀` about a horizontal axis), rising to its full
//! slope at the half turn. It is a function of the *lifted* MRP, not of `R̃`, so it can have a
//! gradient at the half turn (the path lifting's memory says which way to go), and its torque
//! `τ_t = −T(ϑ̃)ᵀ ∇Ψ_t` is `−M_t` about the half turn's axis there.
//!
//! **Why it keeps the certificate.** `∇Ψ_t = 2 M_t b(ρ²)(ϑ₁, ϑ₂, 0)` has no third component, and
//! `(ϑ × ∇Ψ_t)₃ = 0`, so `τ_t,3 = −M_t b ϑ₃ ρ²`: its yaw part is small wherever the term acts
//! (`|ϑ₃| ≤ √((1+δ)² − ρ²)` is small near the half turn). Per-axis bounds over the flow set
//! `|ϑ̃| ≤ 1 + δ` ([`TurnOver::bounds`]): `½ M_t t(1 + t²)` about roll and pitch (`t = 1 + δ`) and
//! `M_t max_s b(s) s √(t² − s)` about yaw, about a fifth of roll's. In the Lyapunov function of
//! tilt priority `Ψ_t` is one more potential: along flows `d/dt Ψ_t = ∇Ψ_tᵀ T(ϑ̃) ω̃ = −τ_tᵀω̃`
//! cancels its torque; at the path lifting's jump `ϑ → −ϑ/|ϑ|²` the horizontal part shrinks
//! (`ρ/|ϑ|² < ρ`) and `Ψ_t` does not grow; along every ray `Ψ_t` is non-decreasing, so it adds no
//! zero of the feedback (the hysteresis-band condition is unchanged).
//!
//! Source: extension (docs/turn-over.md), built on the paper's MRP path lifting (Appendix) and
//! its identity `ϑ̇ = T(ϑ)ω` (Section II).

use nalgebra::Vector3;

use crate::mrp::mrp_kinematics;
use crate::parameter_error::{positive, ParameterError};
use crate::scalar::{lit, to_f64, Scalar};

/// The turn-over term's gains (extension, docs/turn-over.md).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TurnOver<T: Scalar> {
    /// `M_t` [N m]: the torque about the axis of a horizontal half turn, `> 0`.
    pub level: T,
    /// `ρ₀` (dimensionless, in `(0, 1)`): the onset, as the horizontal MRP norm below which the
    /// term is zero (a rotation by `4 atan ρ₀` about a horizontal axis; 0.8 is 154.6°).
    pub onset: T,
}

impl<T: Scalar> TurnOver<T> {
    /// Checks `M_t > 0` and `0 < ρ₀ < 1`, both finite.
    /// Errors: [`ParameterError::NotPositive`] naming `"turn_over_level"`,
    /// [`ParameterError::OutOfRange`] naming `"turn_over_onset"`.
    pub fn validate(&self) -> Result<(), ParameterError> {
        positive("turn_over_level", self.level)?;
        if !(self.onset > T::zero() && self.onset < T::one()) {
            return Err(ParameterError::OutOfRange {
                name: "turn_over_onset",
                value: to_f64(self.onset),
                low: 0.0,
                high: 1.0,
            });
        }
        Ok(())
    }

    /// `b(s) = clamp((s − ρ₀²)/(1 − ρ₀²), 0, 1)` for `s = ρ²`: the slope's share (also read by
    /// the attitude terms' joint bound, `crate::torque_set::attitude_joint`).
    pub(crate) fn share(&self, s: T) -> T {
        let s0 = self.onset * self.onset;
        ((s - s0) / (T::one() - s0)).max(T::zero()).min(T::one())
    }

    /// `∇Ψ_t(ϑ) = 2 M_t b(ρ²)(ϑ₁, ϑ₂, 0)` (dimensionless MRP in, N m out).
    fn gradient(&self, mrp: &Vector3<T>) -> Vector3<T> {
        let s = mrp.x * mrp.x + mrp.y * mrp.y;
        let c = lit::<T>(2.0) * self.level * self.share(s);
        Vector3::new(c * mrp.x, c * mrp.y, T::zero())
    }

    /// `τ_t = −T(ϑ̃)ᵀ ∇Ψ_t(ϑ̃)` [N m], body frame, of the lifted MRP error `ϑ̃` (dimensionless).
    /// Zero while `ϑ̃₁² + ϑ̃₂² ≤ ρ₀²`. Source: extension (docs/turn-over.md).
    pub fn torque(&self, mrp_error: &Vector3<T>) -> Vector3<T> {
        let g = self.gradient(mrp_error);
        if g == Vector3::zeros() {
            return g;
        }
        -(mrp_kinematics(mrp_error).transpose() * g)
    }

    /// `Ψ_t(ϑ̃)` \[J\]: the potential whose body-frame gradient is the torque,
    /// `2 M_t F(ρ²)` with `F(s) = (s − ρ₀²)²/(4(1 − ρ₀²))` on `[ρ₀², 1]`, `(1 − ρ₀²)/4 + (s − 1)/2`
    /// above, 0 below. Source: extension (docs/turn-over.md).
    pub fn potential(&self, mrp_error: &Vector3<T>) -> T {
        let s = mrp_error.x * mrp_error.x + mrp_error.y * mrp_error.y;
        let s0 = self.onset * self.onset;
        let quarter = lit::<T>(0.25);
        let f = if s <= s0 {
            T::zero()
        } else if s <= T::one() {
            (s - s0) * (s - s0) * quarter / (T::one() - s0)
        } else {
            (T::one() - s0) * quarter + (s - T::one()) * lit(0.5)
        };
        lit::<T>(2.0) * self.level * f
    }

    /// Per-axis bounds `(roll, pitch, yaw)` [N m] of `|τ_t,i|` over `|ϑ̃| ≤ 1 + δ` (`hysteresis`
    /// is `δ`). Roll and pitch: the horizontal part has norm
    /// `½ M_t b ρ √((1 + ρ² − ϑ₃²)² + 4ϑ₃²)`, largest at `ρ = 1 + δ`: `½ M_t t(1 + t²)`,
    /// `t = 1 + δ`. Yaw: `M_t max_s b(s) s √(t² − s)` over `s = ρ² ∈ [ρ₀², t²]`, a log-concave
    /// function whose maximum on `[ρ₀², 1]` is at the larger root of
    /// `5s² − (4t² + 3ρ₀²)s + 2t²ρ₀² = 0` (clamped) and on `[1, t²]` at `max(1, 2t²/3)`.
    /// Source: extension (docs/turn-over.md); the property test samples the ball against them.
    pub fn bounds(&self, hysteresis: T) -> Vector3<T> {
        let t = T::one() + hysteresis;
        let t2 = t * t;
        let s0 = self.onset * self.onset;
        let horizontal = lit::<T>(0.5) * self.level * t * (T::one() + t2);
        let f = |s: T| self.share(s) * s * (t2 - s).max(T::zero()).sqrt_ieee();
        let a = lit::<T>(4.0) * t2 + lit::<T>(3.0) * s0;
        let disc = (a * a - lit::<T>(40.0) * t2 * s0).max(T::zero());
        let inner = ((a + disc.sqrt_ieee()) / lit(10.0)).max(s0).min(T::one());
        let outer = (t2 * lit(2.0) / lit(3.0)).max(T::one()).min(t2);
        let yaw = self.level * f(inner).max(f(T::one())).max(f(outer));
        Vector3::new(horizontal, horizontal, yaw)
    }
}

#[cfg(test)]
mod tests;
