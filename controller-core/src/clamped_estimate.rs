//! A clamped, rate-limited estimate and its first-order output filter, per axis: the one
//! mechanism behind the integral action's estimate ([`crate::integral`]) and the feedforward
//! scale's ([`crate::feedforward_scale`]), with the reachable-set bound on the filtered rate
//! that the certificate adds to Lemma 1.
//!
//! Source: extension, docs/integral-action.md (not in the paper); the derivation of the
//! reachable-set bound is in [`crate::integral`]'s module docs.

use crate::scalar::{lit, Scalar};

/// Longest sample over which the estimate moves \[s\] (the slowest control rate, 100 Hz): a
/// longer sample advances it by at most `R_i` times this, which keeps the reachable-set bound
/// ([`crate::integral::IntegralGains::filtered_rate_bound`]) independent of timing jitter.
pub const MAX_ESTIMATE_STEP_S: f64 = 0.01;

/// Shortest control period the reachable-set bound's rounding term covers \[s\] (the fastest
/// control rate, 1 kHz): the scalar type's rounding of the filter's propagation accumulates
/// over about `1/(k_η h)` samples, so shorter samples accumulate more of it.
pub const MIN_CONTROL_PERIOD_S: f64 = 0.001;

/// `c = x/(1 − e^{−x})` with `x = k_η h_max` (dimensionless, `≥ 1`) for the output filter's
/// bandwidth `k_η` [1/s]: the factor of the reachable-set bound (module docs).
pub(crate) fn sample_factor<T: Scalar>(bandwidth: T) -> T {
    let x = bandwidth * lit::<T>(MAX_ESTIMATE_STEP_S);
    x / (T::one() - (-x).exp())
}

/// The reachable-set bound on the filtered rate of one clamped, rate-limited estimate with
/// level `level`, rate limit `rate` and output-filter bandwidth `bandwidth` (module docs):
/// `min(2 k_η M, c (R + 16 ε M / h_min))`, in the estimate's unit per second.
pub(crate) fn filtered_rate_bound<T: Scalar>(bandwidth: T, rate: T, level: T) -> T {
    let rounding = lit::<T>(16.0) * T::default_epsilon() / lit::<T>(MIN_CONTROL_PERIOD_S);
    let reachable = sample_factor(bandwidth) * (rate + rounding * level);
    let anywhere = lit::<T>(2.0) * bandwidth * level;
    if reachable < anywhere {
        reachable
    } else {
        anywhere
    }
}

/// One estimate's rate from its raw rate: clamped to `±rate`, and zero when the estimate sits at
/// its level `±level` and the raw rate pushes outwards (the estimate's clamp holds it there).
pub(crate) fn clamped_rate<T: Scalar>(raw: T, rate: T, estimate: T, level: T) -> T {
    let r = raw.clamp(-rate, rate);
    let outward = (estimate >= level && r > T::zero()) || (estimate <= -level && r < T::zero());
    if outward {
        T::zero()
    } else {
        r
    }
}

/// The length over which an estimate moves in a sample of `h` \[s\]: `min(h, h_max)`
/// ([`MAX_ESTIMATE_STEP_S`]).
pub(crate) fn estimate_step<T: Scalar>(h: T) -> T {
    let h_max = lit::<T>(MAX_ESTIMATE_STEP_S);
    if h > h_max {
        h_max
    } else {
        h
    }
}

/// One estimate and its filtered output `(estimate, filtered)` after a sample: the filter by its
/// exact solution with the estimate held (`decay = e^{−k_η h}`), then the estimate by one clamped
/// Euler step of length `step` at `rate`; both clamped to `±level`.
pub(crate) fn advance_clamped<T: Scalar>(
    (estimate, filtered): (T, T),
    rate: T,
    level: T,
    decay: T,
    step: T,
) -> (T, T) {
    let filtered = estimate + (filtered - estimate) * decay;
    (
        (estimate + step * rate).clamp(-level, level),
        filtered.clamp(-level, level),
    )
}
