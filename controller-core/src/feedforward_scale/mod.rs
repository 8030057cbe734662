//! Feedforward scale: a bounded estimate of the fraction by which the reference's acceleration
//! feedforward `p̈_d` must be scaled, so that a constant mass or thrust-coefficient error leaves
//! no periodic residual on an accelerating reference.
//!
//! Source: extension, docs/integral-action.md ("Feedforward scale"), not in the paper.
//!
//! **Why.** The law asks for the acceleration `u = u_f + η_f + g e₃ + p̈_d` and applies
//! `T = m|u|` (Section IV). A plant whose mass is `(1 + E) m` (or whose rotors give `1/(1 + E)` of
//! the modelled thrust) accelerates by `u/(1 + E) − g e₃`: the disturbance is
//! `−E/(1 + E) · (g e₃ + p̈_d)`. The integral action's `η` ([`crate::integral`]) cancels its
//! constant part `E g e₃`; the part `E p̈_d` moves with the reference (it turns with a helix), so a
//! constant estimate leaves a periodic residual. This module scales the feedforward instead:
//! `u = u_f + η_f + g e₃ + (1 + μ_f) p̈_d`. With `μ_f = E` and `η_f = E g e₃` the plant tracks
//! exactly, whatever the reference's acceleration.
//!
//! **Estimate.** A scalar `μ` driven by the turning part of the integral action's estimate,
//! `η − η_f` (`η` high-passed by its own output filter: the constant part, a force or the
//! weight, drops out), projected on the reference's acceleration `a = p̈_d`:
//! `μ̇ = clamp(λ ((η − η_f)·a)/(a₀² + |a|²), ±R_μ)`, then `μ ← clamp(μ + h μ̇, ±μ̄)`. While
//! `μ ≠ E` the observer's `η` carries a part `≈ (E − μ)/(1 + E) · a` that turns with the
//! reference, so the projection has the sign of `E − μ`; at `μ = E` it is gone and `μ` stops.
//! On a reference that does not accelerate `a = 0` and `μ` does not move: there the integral
//! action alone takes the constant part. `μ` adapts only near the reference (every
//! `|z₁,i| ≤ z̄_μ`): in a large transient `η` moves with the transient, not with a mass error.
//! The observer's model subtracts what both estimates compensate, `η + μ a`
//! ([`crate::integral::modelled_compensation`]).
//!
//! **Output.** `μ_f`, `μ̇_f = −k_η (μ_f − μ)`, `μ̈_f = −k_η (μ̇_f − μ̇)`: the same output filter as
//! `η` (its bandwidth `k_η`), exact propagation, closed-form derivatives.
//!
//! **Bounds.** The scaled feedforward `(1 + μ_f) p̈_d` is the acceleration of a reference whose
//! Assumption 1 constants are ([`FeedforwardScaleGains::constants`])
//! `K_a' = (1 + μ̄) K_a`, `K_j' = (1 + μ̄) K_j + b |K_a|`,
//! `K_s' = (1 + μ̄) K_s + 2 b K_j + k_η (b + R_μ) |K_a|`, with `b` the reachable-set bound on
//! `|μ̇_f|` (the one the integral's estimate uses, [`crate::integral`]): the law's `u`, `u̇`, `ü`
//! see the reference only through `p̈_d`, `p⃛_d`, `p⁗_d`, so Theorem 1, Lemma 1 and Theorem 2 hold
//! with those constants, unchanged otherwise. [`crate::certify`] uses them.

use nalgebra::Vector3;

use crate::clamped_estimate::{advance_clamped, clamped_rate, estimate_step, filtered_rate_bound};
use crate::parameter_error::{positive, ParameterError};
use crate::reference::{ReferenceSample, TrajectoryConstants};
use crate::scalar::{lit, to_f64, Scalar};

/// Gains and levels of the feedforward scale (extension, docs/integral-action.md).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FeedforwardScaleGains<T: Scalar> {
    /// `λ` [1/s]: adaptation gain, `μ̇ = λ ((η − η_f)·a)/(a₀² + |a|²)` before the clamps
    /// (`a = p̈_d`; the fraction is dimensionless).
    pub gain: T,
    /// `a₀` [m/s²]: the normalisation's floor; references accelerating much less than `a₀`
    /// move the estimate little.
    pub excitation: T,
    /// `μ̄` (dimensionless, in `(0, 1)`): saturation level, `|μ| ≤ μ̄` (the mass or
    /// thrust-coefficient error covered, as a fraction).
    pub level: T,
    /// `R_μ` [1/s]: rate limit, `|μ̇| ≤ R_μ`.
    pub rate: T,
    /// `z̄_μ` \[m\]: `μ` adapts only while every `|z₁,i| ≤ z̄_μ`; farther from the reference the
    /// integral's estimate moves with the transient (a flip, a start metres away), not with a
    /// mass error.
    pub tracking_limit: T,
}

/// The feedforward scale's state (dimensionless).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FeedforwardScaleState<T: Scalar> {
    /// `μ`: the saturated, rate-limited estimate.
    pub estimate: T,
    /// `μ_f`: the filtered estimate, the one the law applies.
    pub filtered: T,
}

impl<T: Scalar> FeedforwardScaleState<T> {
    /// `μ = μ_f = 0` (arming).
    pub fn zero() -> Self {
        Self {
            estimate: T::zero(),
            filtered: T::zero(),
        }
    }
}

/// What the feedforward scale adds to the position law at one sample [m/s², m/s³, m/s⁴],
/// inertial.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FeedforwardScaleOutput<T: Scalar> {
    /// `μ_f p̈_d`, added to `u`.
    pub u: Vector3<T>,
    /// `μ̇_f p̈_d + μ_f p⃛_d`, added to `u̇`.
    pub u_dot: Vector3<T>,
    /// `μ̈_f p̈_d + 2 μ̇_f p⃛_d + μ_f p⁗_d`, added to `ü`.
    pub u_ddot: Vector3<T>,
}

impl<T: Scalar> FeedforwardScaleGains<T> {
    /// Checks `λ, a₀, R_μ, z̄_μ > 0` and `0 < μ̄ < 1` (all finite).
    /// Errors: [`ParameterError::NotPositive`] naming `"mu_gain"`, `"mu_excitation"`,
    /// `"mu_rate"`, `"mu_tracking_limit"`; [`ParameterError::OutOfRange`] naming `"mu_level"` (bounds `(0, 1)`).
    pub fn validate(&self) -> Result<(), ParameterError> {
        positive("mu_gain", self.gain)?;
        positive("mu_excitation", self.excitation)?;
        positive("mu_rate", self.rate)?;
        positive("mu_tracking_limit", self.tracking_limit)?;
        if self.level > T::zero() && self.level < T::one() {
            Ok(())
        } else {
            Err(ParameterError::OutOfRange {
                name: "mu_level",
                value: to_f64(self.level),
                low: 0.0,
                high: 1.0,
            })
        }
    }

    /// The rate `μ̇` [1/s] used over the coming sample, from the turning part of the integral
    /// action's estimate `moving = η − η_f` [m/s²], the reference's acceleration
    /// `acceleration` [m/s²] and the forward-projected position error `z1` \[m\] (all
    /// inertial): `λ (moving·a)/(a₀² + |a|²)` clamped to `±R_μ`; zero when `μ` sits at its level
    /// and would be pushed outwards, when some `|z₁,i| > z̄_μ`, or when `frozen`.
    pub fn rate_of(
        &self,
        state: &FeedforwardScaleState<T>,
        moving: &Vector3<T>,
        acceleration: &Vector3<T>,
        z1: &Vector3<T>,
        frozen: bool,
    ) -> T {
        if frozen || z1.amax() > self.tracking_limit {
            return T::zero();
        }
        let a0 = self.excitation;
        let normalised = moving.dot(acceleration) / (a0 * a0 + acceleration.norm_squared());
        clamped_rate(
            self.gain * normalised,
            self.rate,
            state.estimate,
            self.level,
        )
    }

    /// Bound on `|μ̇_f|` [1/s] at every sample reachable from the zero state (the integral
    /// action's reachable-set bound, docs/integral-action.md, with `k_η = bandwidth` [1/s]).
    pub fn filtered_rate_bound(&self, bandwidth: T) -> T {
        filtered_rate_bound(bandwidth, self.rate, self.level)
    }

    /// Bound on `|μ̈_f|` [1/s²]: `k_η (b + R_μ)` with [`Self::filtered_rate_bound`].
    pub fn filtered_acceleration_bound(&self, bandwidth: T) -> T {
        (self.filtered_rate_bound(bandwidth) + self.rate) * bandwidth
    }

    /// The Assumption 1 constants of the scaled feedforward `(1 + μ_f) p̈_d` for a reference with
    /// constants `k` (module docs): accelerations times `1 + μ̄`; `K_j` and `K_s` gain the terms
    /// of `μ̇_f`, `μ̈_f`. The heading's constants are unchanged. `bandwidth` = `k_η` [1/s].
    /// Source: extension, docs/integral-action.md.
    pub fn constants(&self, k: &TrajectoryConstants<T>, bandwidth: T) -> TrajectoryConstants<T> {
        let scale = T::one() + self.level;
        let b = self.filtered_rate_bound(bandwidth);
        let a = self.filtered_acceleration_bound(bandwidth);
        let acceleration = (k.horizontal_acceleration * k.horizontal_acceleration
            + k.vertical_acceleration * k.vertical_acceleration)
            .sqrt();
        let two = lit::<T>(2.0);
        TrajectoryConstants {
            horizontal_acceleration: scale * k.horizontal_acceleration,
            vertical_acceleration: scale * k.vertical_acceleration,
            jerk: scale * k.jerk + b * acceleration,
            snap: scale * k.snap + two * b * k.jerk + a * acceleration,
            ..*k
        }
    }

    /// `μ_f p̈_d` and its closed-form derivatives at the sample, given the rate `μ̇` from
    /// [`Self::rate_of`] and `bandwidth` = `k_η` [1/s].
    pub fn output(
        &self,
        state: &FeedforwardScaleState<T>,
        rate: T,
        bandwidth: T,
        reference: &ReferenceSample<T>,
    ) -> FeedforwardScaleOutput<T> {
        let mu = state.filtered;
        let mu_dot = (state.filtered - state.estimate) * (-bandwidth);
        let mu_ddot = (mu_dot - rate) * (-bandwidth);
        let (a, j, s) = (&reference.acceleration, &reference.jerk, &reference.snap);
        let two = lit::<T>(2.0);
        FeedforwardScaleOutput {
            u: a * mu,
            u_dot: a * mu_dot + j * mu,
            u_ddot: a * mu_ddot + j * (two * mu_dot) + s * mu,
        }
    }

    /// The state after a sample of `h` \[s\] with the rate `μ̇` [1/s]: the filter by its exact
    /// solution with `μ` held, `μ` by one clamped Euler step of length `min(h, h_max)`
    /// (as the integral's estimate, [`crate::integral::MAX_ESTIMATE_STEP_S`]); both stay in
    /// `[−μ̄, μ̄]`.
    pub fn advance(
        &self,
        state: &FeedforwardScaleState<T>,
        rate: T,
        bandwidth: T,
        h: T,
    ) -> FeedforwardScaleState<T> {
        let decay = (-bandwidth * h).exp();
        let (estimate, filtered) = advance_clamped(
            (state.estimate, state.filtered),
            rate,
            self.level,
            decay,
            estimate_step(h),
        );
        FeedforwardScaleState { estimate, filtered }
    }
}

#[cfg(test)]
mod tests;
