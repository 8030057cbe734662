//! Bounded integral action: a saturated, rate-limited estimate of the constant part of the
//! position disturbance, and its first-order output filter.
//!
//! Source: extension, docs/integral-action.md (not in the paper). Per inertial axis `i`:
//!
//! * the estimate `η` integrates the forward-projected position error `z₁` (eq:Zcoordinates)
//!   at a clamped rate, and is itself clamped: over a sample of length `h`,
//!   `η ← clamp(η + h · clamp(−k_i z₁, −R, R), −M_i, M_i)`. Wind-up is impossible by
//!   construction: `|η_i| ≤ M_i,i` always, whatever `z₁` does;
//! * the law uses the filtered estimate `η_f`, `η̇_f = −k_η (η_f − η)`, propagated by its exact
//!   solution with `η` held over the sample: `η_f ← η + (η_f − η) e^{−k_η h}`, a convex
//!   combination, so `|η_f,i| ≤ M_i,i` too;
//! * the derivatives the attitude reference needs are in closed form (never differenced):
//!   `η̇_f = −k_η (η_f − η)` and `η̈_f = −k_η (η̇_f − η̇)`, with `η̇` the clamped rate used over the
//!   coming sample. Hence `|η̇_f,i| ≤ 2 k_η M_i,i` and `|η̈_f,i| ≤ k_η (|η̇_f,i| + R_i)`;
//! * **reachable-set bound** on `η̇_f` ([`IntegralGains::filtered_rate_bound`]): the state starts
//!   at `η = η_f = 0` ([`IntegralState::zero`], at arming) and is only ever changed by
//!   [`IntegralGains::advance`], whose estimate step is at most `R_i min(h, h_max)`
//!   ([`MAX_ESTIMATE_STEP_S`]: a late sample moves the estimate no further than an on-time one).
//!   With `e = η − η_f` at a sample, one advance gives `e' = Δη + e^{−k_η h} e`, so
//!   `|e'| ≤ R_i s + e^{−k_η s} |e|` (`s = min(h, h_max)`), and `|e| ≤ (R_i/k_η) c` with
//!   `c = x/(1 − e^{−x})`, `x = k_η h_max`, is invariant (the right side of the step grows with
//!   `s`). Hence `|η̇_f,i| = k_η |e_i| ≤ c R_i`, however long the estimate has been driven, which
//!   is far below `2 k_η M_i,i` when the estimate's rate is limited (`R_i ≪ 2 k_η M_i,i`); a few
//!   units of rounding of the scalar type are added. These are the terms [`crate::certify`]
//!   adds to Lemma 1.
//!
//! The position law with the integral on is `u = u_f + η_f + g e₃ + p̈_d`; in equilibrium under a
//! constant acceleration disturbance `d`, `η_f = η = −d` and `z₁ = z₂ = 0`, `p̃ = 0`.

use nalgebra::Vector3;

use crate::clamped_estimate::{
    advance_clamped, clamped_rate, estimate_step, filtered_rate_bound, sample_factor,
};
pub use crate::clamped_estimate::{MAX_ESTIMATE_STEP_S, MIN_CONTROL_PERIOD_S};
use crate::disturbance_observer::ObserverGains;
use crate::feedforward_scale::{FeedforwardScaleGains, FeedforwardScaleState};
use crate::parameter_error::{positive, ParameterError};
use crate::scalar::Scalar;

/// Gains and levels of the integral action (extension, docs/integral-action.md).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IntegralGains<T: Scalar> {
    /// `k_i` [1/s³]: integral gain on `z₁` \[m\] (the estimate's rate is `−k_i z₁` [m/s³] before
    /// clamping).
    pub gain: T,
    /// `M_i` [m/s²] per inertial axis: saturation level of the estimate, `|η_i| ≤ M_i,i`.
    pub level: Vector3<T>,
    /// `R_i` [m/s³] per inertial axis: rate limit of the estimate, `|η̇_i| ≤ R_i,i`.
    pub rate: Vector3<T>,
    /// `k_η` [1/s]: bandwidth of the output filter producing `η_f`.
    pub bandwidth: T,
    /// With `Some`, a velocity disturbance observer anchors the estimate
    /// ([`crate::disturbance_observer`]): the raw rate becomes `−k_i sat(z₁) − L_d (v − v̂)`.
    /// `None`: the integral of `z₁` alone.
    pub observer: Option<ObserverGains<T>>,
    /// With `Some`, a bounded estimate of the fraction by which the reference's acceleration
    /// feedforward must be scaled (a mass or thrust-coefficient error;
    /// [`crate::feedforward_scale`]). `None`: the feedforward is the paper's `p̈_d`.
    pub feedforward_scale: Option<FeedforwardScaleGains<T>>,
}

impl<T: Scalar> IntegralGains<T> {
    /// Checks `k_i, k_η > 0` and every component of `M_i`, `R_i` `> 0` (all finite).
    /// Errors: [`ParameterError::NotPositive`] naming the first offender (`"k_i"`, `"M_i_x"`, ...).
    pub fn validate(&self) -> Result<(), ParameterError> {
        positive("k_i", self.gain)?;
        positive("k_eta", self.bandwidth)?;
        for (name, v) in ["M_i_x", "M_i_y", "M_i_z"].iter().zip(self.level.iter()) {
            positive(name, *v)?;
        }
        for (name, v) in ["R_i_x", "R_i_y", "R_i_z"].iter().zip(self.rate.iter()) {
            positive(name, *v)?;
        }
        if let Some(o) = &self.observer {
            o.validate()?;
        }
        match &self.feedforward_scale {
            Some(f) => f.validate(),
            None => Ok(()),
        }
    }

    /// The clamped rate `η̇` [m/s³] used over the coming sample: `clamp(−k_i z₁, −R, R)`, and
    /// zero on an axis whose estimate sits at its level and would be pushed outwards (there the
    /// clamp of the estimate holds it, so its true rate is zero). Zero everywhere when `frozen`.
    pub fn rate_of(&self, state: &IntegralState<T>, z1: &Vector3<T>, frozen: bool) -> Vector3<T> {
        self.clamped_rate(state, &(z1 * (-self.gain)), frozen)
    }

    /// The rate `η̇` [m/s³] from a raw rate (before clamping; e.g. the observer's
    /// [`ObserverGains::raw_rate`]): clamped to `±R`, zero on an axis whose estimate sits at its
    /// level and would be pushed outwards, zero everywhere when `frozen`.
    pub fn clamped_rate(
        &self,
        state: &IntegralState<T>,
        raw: &Vector3<T>,
        frozen: bool,
    ) -> Vector3<T> {
        if frozen {
            return Vector3::zeros();
        }
        Vector3::from_fn(|i, _| {
            clamped_rate(raw[i], self.rate[i], state.estimate[i], self.level[i])
        })
    }

    /// `c = x/(1 − e^{−x})` with `x = k_η h_max` (dimensionless, `≥ 1`): the factor of the
    /// reachable-set bound (module docs).
    pub fn sample_factor(&self) -> T {
        sample_factor(self.bandwidth)
    }

    /// Per-axis bound on `|η̇_f,i|` [m/s³] at every sample reachable from
    /// [`IntegralState::zero`]: `min(2 k_η M_i,i, c (R_i,i + 16 ε M_i,i / h_min))`, the second
    /// the reachable-set bound of the module docs with the scalar type's rounding (`ε` its
    /// machine epsilon; about `4 ε M_i` per sample, accumulated over `1/(k_η h)` samples, four
    /// times over for samples down to [`MIN_CONTROL_PERIOD_S`]) of the filter's propagation
    /// added. Source: extension, docs/integral-action.md.
    pub fn filtered_rate_bound(&self) -> Vector3<T> {
        Vector3::from_fn(|i, _| filtered_rate_bound(self.bandwidth, self.rate[i], self.level[i]))
    }

    /// Per-axis bound on `|η̈_f,i|` [m/s⁴]: `k_η (|η̇_f,i| + R_i,i)` with
    /// [`Self::filtered_rate_bound`]. Source: extension, docs/integral-action.md.
    pub fn filtered_acceleration_bound(&self) -> Vector3<T> {
        (self.filtered_rate_bound() + self.rate) * self.bandwidth
    }

    /// `η_f` [m/s²] and its closed-form derivatives [m/s³], [m/s⁴] at the sample, given the
    /// rate `η̇` from [`Self::rate_of`]. All inertial.
    pub fn output(&self, state: &IntegralState<T>, rate: &Vector3<T>) -> IntegralOutput<T> {
        let filtered_dot = (state.filtered - state.estimate) * (-self.bandwidth);
        let filtered_ddot = (filtered_dot - rate) * (-self.bandwidth);
        IntegralOutput {
            filtered: state.filtered,
            filtered_dot,
            filtered_ddot,
        }
    }

    /// Advances the state over a sample of length `h` \[s\] with the rate `η̇` [m/s³] (from
    /// [`Self::rate_of`]): the filter by its exact solution with the current estimate held, then
    /// the estimate by one clamped Euler step of length `min(h, h_max)`
    /// ([`MAX_ESTIMATE_STEP_S`]; the reachable-set bound needs it). Both stay in `[−M_i, M_i]`
    /// per axis if they start there (the filter output is a convex combination of two values in
    /// the box).
    pub fn advance(&self, state: &IntegralState<T>, rate: &Vector3<T>, h: T) -> IntegralState<T> {
        let decay = (-self.bandwidth * h).exp();
        let step = estimate_step(h);
        let mut next = IntegralState::zero();
        for i in 0..3 {
            (next.estimate[i], next.filtered[i]) = advance_clamped(
                (state.estimate[i], state.filtered[i]),
                rate[i],
                self.level[i],
                decay,
                step,
            );
        }
        next
    }
}

/// The integral action's state, inertial frame [m/s²].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IntegralState<T: Scalar> {
    /// `η` [m/s²]: the saturated, rate-limited estimate of minus the constant disturbance.
    pub estimate: Vector3<T>,
    /// `η_f` [m/s²]: the filtered estimate, the one the law applies.
    pub filtered: Vector3<T>,
}

impl<T: Scalar> IntegralState<T> {
    /// `η = η_f = 0` (arming).
    pub fn zero() -> Self {
        Self {
            estimate: Vector3::zeros(),
            filtered: Vector3::zeros(),
        }
    }
}

/// What the integral action contributes at one sample (inertial).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IntegralOutput<T: Scalar> {
    /// `η_f` [m/s²], added to `u`.
    pub filtered: Vector3<T>,
    /// `η̇_f = −k_η (η_f − η)` [m/s³], added to `u̇`.
    pub filtered_dot: Vector3<T>,
    /// `η̈_f = −k_η (η̇_f − η̇)` [m/s⁴], added to `ü`.
    pub filtered_ddot: Vector3<T>,
}

/// The disturbance the observer's model subtracts [m/s²], inertial: `η + μ p̈_d`, the two
/// estimates together (`μ = 0` without the feedforward scale).
pub fn modelled_compensation<T: Scalar>(
    integral: &IntegralState<T>,
    scale: &FeedforwardScaleState<T>,
    acceleration: &Vector3<T>,
) -> Vector3<T> {
    integral.estimate + acceleration * scale.estimate
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use proptest::prelude::*;

    fn gains() -> IntegralGains<f64> {
        IntegralGains {
            gain: 2.0,
            level: Vector3::new(0.5, 0.7, 1.5),
            rate: Vector3::new(0.4, 0.6, 1.0),
            bandwidth: 5.0,
            observer: None,
            feedforward_scale: None,
        }
    }

    fn v3(r: f64) -> impl Strategy<Value = Vector3<f64>> {
        (-r..r, -r..r, -r..r).prop_map(|(a, b, c)| Vector3::new(a, b, c))
    }

    proptest! {
        /// Whatever z₁ does (including huge errors held for long), η and η_f stay in
        /// [−M_i, M_i] per axis and η moves at most R_i h per sample: no wind-up.
        #[test]
        fn estimate_never_leaves_its_box(
            z1s in proptest::collection::vec(v3(100.0), 1..400),
            h in 0.0005..0.5f64,
            gain in 0.01..50.0f64,
            bandwidth in 0.01..200.0f64,
            frozen_from in 0usize..400,
        ) {
            let g = IntegralGains { gain, bandwidth, ..gains() };
            let mut s = IntegralState::zero();
            for (k, z1) in z1s.iter().enumerate() {
                let frozen = k >= frozen_from;
                let rate = g.rate_of(&s, z1, frozen);
                let out = g.output(&s, &rate);
                let next = g.advance(&s, &rate, h);
                for i in 0..3 {
                    prop_assert!(next.estimate[i].abs() <= g.level[i]);
                    prop_assert!(next.filtered[i].abs() <= g.level[i]);
                    let step = h.min(MAX_ESTIMATE_STEP_S);
                    prop_assert!((next.estimate[i] - s.estimate[i]).abs() <= g.rate[i] * step * (1.0 + 1e-12));
                    prop_assert!(rate[i].abs() <= g.rate[i]);
                    // The a-priori bounds certify adds to Lemma 1: the reachable-set ones, and
                    // the whole-box ones they never exceed.
                    let (rate_bound, acceleration_bound) =
                        (g.filtered_rate_bound()[i], g.filtered_acceleration_bound()[i]);
                    prop_assert!(out.filtered_dot[i].abs() <= rate_bound,
                        "|eta_f dot| {} > {rate_bound}", out.filtered_dot[i].abs());
                    prop_assert!(out.filtered_ddot[i].abs() <= acceleration_bound,
                        "|eta_f ddot| {} > {acceleration_bound}", out.filtered_ddot[i].abs());
                    prop_assert!(rate_bound <= 2.0 * g.bandwidth * g.level[i]);
                    if frozen {
                        prop_assert_eq!(next.estimate[i], s.estimate[i]);
                    }
                }
                s = next;
            }
        }

        /// η̇_f agrees with a central difference of the exact filter solution with η held
        /// (η_f(t) = η + (η_f − η) e^{−k_η t}), which the advance step samples.
        #[test]
        fn filtered_derivative_is_the_flow(eta in v3(0.5), etaf in v3(0.5), h in 1e-5..1e-4f64) {
            let g = gains();
            let s = IntegralState { estimate: eta, filtered: etaf };
            let zero = Vector3::zeros();
            let out = g.output(&s, &zero);
            let at = |t: f64| eta + (etaf - eta) * (-g.bandwidth * t).exp();
            let fd = (at(h) - at(-h)) / (2.0 * h);
            let fd2 = (at(h) - etaf * 2.0 + at(-h)) / (h * h);
            assert_relative_eq!(out.filtered_dot, fd, epsilon = 1e-6);
            // With η held (rate 0) the second derivative is k_η² (η_f − η). Tolerance: rounding
            // of the second difference ≤ 4ε·1/h² ≈ 9e-6, truncation ≤ k_η⁴ h² / 12 ≈ 5e-7.
            assert_relative_eq!(out.filtered_ddot, fd2, epsilon = 1e-5);
            let next = g.advance(&s, &zero, h);
            assert_relative_eq!(next.filtered, at(h), epsilon = 1e-15);
        }
    }

    #[test]
    fn saturated_estimate_does_not_push_outwards() {
        let g = gains();
        let s = IntegralState {
            estimate: g.level,
            filtered: g.level,
        };
        // z₁ < 0 drives η upwards, into the level: the rate is zero there.
        let rate = g.rate_of(&s, &Vector3::repeat(-10.0), false);
        assert_eq!(rate, Vector3::zeros());
        // The other way it moves at the rate limit.
        let rate = g.rate_of(&s, &Vector3::repeat(10.0), false);
        assert_eq!(rate, -g.rate);
    }

    #[test]
    fn refuses_bad_gains_by_name() {
        let mut g = gains();
        g.level.y = -1.0;
        assert_eq!(
            g.validate(),
            Err(ParameterError::NotPositive {
                name: "M_i_y",
                value: -1.0
            })
        );
        let mut g = gains();
        g.bandwidth = f64::NAN;
        assert!(matches!(
            g.validate(),
            Err(ParameterError::NotPositive { name: "k_eta", .. })
        ));
    }
}
