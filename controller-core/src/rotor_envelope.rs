//! The rotors' `(T, τ)` set, how much of it a certified set leaves free, and airmode: the
//! collective thrust moved, as little as possible, to where the rotors realise the law's torque
//! (extension, docs/airmode.md).
//!
//! Rotor `k` receives `f_k = w_k T + c_kᵀτ` (`(w_k, c_k)` its row of the mixer `M = B⁻¹`,
//! `w_k > 0`) and must stay in `[lo, hi]`. For a torque `τ` the collective thrusts the rotors
//! realise form the interval `A(τ) = [max_k (lo − c_kᵀτ)/w_k, min_k (hi − c_kᵀτ)/w_k]`.
//!
//! - **The set fit** ([`RotorEnvelope::set_margin`]): `[T_lo, T_hi] × S` lies in the rotors'
//!   set iff every rotor's extremes `w_k T_hi + h_S(c_k)` and `w_k T_lo − h_S(c_k)` do (`h_S` the
//!   support function of the torque set `S`, [`TorqueSet::support`]). Both ends of the thrust
//!   interval must hold every torque: high thrust and large torque exclude each other.
//! - **The shadow fit** ([`RotorEnvelope::shadow_margin`]): `A(τ)` is not empty for any
//!   `τ ∈ S` iff for every ordered pair of rotors `(k, l)`,
//!   `h_S(w_k c_l − w_l c_k) ≤ w_k hi − w_l lo` (Fourier–Motzkin on the two ends of `A(τ)`):
//!   every torque of `S` is realised at *some* thrust, the rotors' torque authority at the best
//!   thrust for it.
//! - **Airmode** ([`RotorEnvelope::airmode_thrust`]): the law's thrust `T` clamped into `A(τ)`.
//!   Where `T ∈ A(τ)` it is unchanged; otherwise it moves to the nearest thrust at which the
//!   rotors realise `τ` exactly. With the shadow fit, every `(T, τ)` the law then applies is in
//!   the rotors' set, so the mixer gives nothing up and the torque of Theorem 2 is applied as
//!   the law computed it.
//!
//! The airmode thrust equals the law's wherever the law's `(T, τ)` already fits; the thrust
//! differs from `m|u|` only while the torque needs it, which the convergence argument of
//! docs/airmode.md bounds by the attitude error.

use nalgebra::Vector3;

use crate::parameter_error::ParameterError;
use crate::scalar::{to_f64, Scalar};
use crate::torque_set::TorqueSet;

mod binding;
pub use binding::ShadowBinding;

/// The rotors' `(T, τ)` set of an X quad (or any four rotors that all carry collective): rows
/// `(w_k, c_k)` of the mixer `M = B⁻¹` (`f_k = w_k T + c_kᵀτ`; `w_k` dimensionless, `c_k` [1/m],
/// body axes) and the per-rotor thrust range `[lo, hi]` \[N\] (shrunk by a margin where the
/// caller keeps one, [`RotorEnvelope::shrunk`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RotorEnvelope<T: Scalar> {
    /// Collective share `w_k` of each rotor (each `> 0`).
    pub collective: [T; 4],
    /// Torque row `c_k` of each rotor [1/m], body axes.
    pub torque: [Vector3<T>; 4],
    /// Per-rotor thrust range `(lo, hi)` \[N\], `0 ≤ lo < hi`.
    pub range: (T, T),
}

impl<T: Scalar> RotorEnvelope<T> {
    /// The envelope of the mixer rows `rows` (row `k` = `(w_k, c_k,x, c_k,y, c_k,z)`) and the
    /// range `[lo, hi]` \[N\].
    /// Errors: [`ParameterError::NotPositive`] naming `"mixer collective share"` when a `w_k` is
    /// not positive (a rotor that cannot carry collective), `"mixer row"` when a row is not
    /// finite; [`ParameterError::OutOfRange`] naming `"rotor thrust range"` unless
    /// `0 ≤ lo < hi`, both finite.
    pub fn new(rows: [[T; 4]; 4], lo: T, hi: T) -> Result<Self, ParameterError> {
        if !(lo.is_finite() && hi.is_finite() && lo >= T::zero() && hi > lo) {
            return Err(ParameterError::OutOfRange {
                name: "rotor thrust range",
                value: to_f64(hi - lo),
                low: 0.0,
                high: f64::INFINITY,
            });
        }
        for r in &rows {
            if !r.iter().all(|x| x.is_finite()) {
                return Err(ParameterError::NotPositive {
                    name: "mixer row",
                    value: f64::NAN,
                });
            }
            if r[0] <= T::zero() {
                return Err(ParameterError::NotPositive {
                    name: "mixer collective share",
                    value: to_f64(r[0]),
                });
            }
        }
        Ok(Self {
            collective: rows.map(|r| r[0]),
            torque: rows.map(|r| Vector3::new(r[1], r[2], r[3])),
            range: (lo, hi),
        })
    }

    /// The same rotors with their range shrunk by `margin` (fraction of `hi − lo`) at both ends.
    /// No errors; a `margin` of 0.5 or more leaves an empty range (nothing fits it).
    pub fn shrunk(&self, margin: T) -> Self {
        self.shrunk_ends(margin, margin)
    }

    /// The same rotors with their range shrunk by `low` above its least thrust and by `high`
    /// below its greatest (fractions of `hi − lo`). Airmode flies the range with a smaller `low`
    /// than the fits were checked with: every range it contains holds what those fits certify,
    /// so the set still fits, and the thrust can fall closer to the rotors' idle while the
    /// no-dive thrust cuts it (docs/airmode.md). No errors; `low + high ≥ 1` leaves an empty
    /// range (nothing fits it).
    pub fn shrunk_ends(&self, low: T, high: T) -> Self {
        let (lo, hi) = self.range;
        let span = hi - lo;
        Self {
            range: (lo + low * span, hi - high * span),
            ..*self
        }
    }

    /// The smallest headroom the set `T ∈ [t_lo, t_hi]`, `τ ∈ set` leaves inside the rotor
    /// range, as a fraction of `hi − lo`: rotor `k`'s extremes over the set are
    /// `w_k t_hi + h(c_k)` and `w_k t_lo − h(c_k)` (linear, so exact). Negative when it does not
    /// fit. Source: extension of Theorem 2 (docs/torque-set.md).
    pub fn set_margin(&self, t_lo: T, t_hi: T, set: &TorqueSet<T>) -> T {
        let (lo, hi) = self.range;
        let mut margin = T::max_value().unwrap_or_else(T::one);
        for k in 0..4 {
            let w = self.collective[k];
            let h = set.support(&self.torque[k]);
            margin = margin.min(hi - (w * t_hi + h)).min(w * t_lo - h - lo);
        }
        margin / (hi - lo)
    }

    /// The largest `m` (fraction of `hi − lo`) such that every torque of `set` is realised at
    /// some collective thrust with the range shrunk by `m` at both ends: the least over ordered
    /// pairs `(k, l)`, `k ≠ l`, of `(w_k hi − w_l lo − h(w_k c_l − w_l c_k)) / ((w_k + w_l)(hi − lo))`
    /// (module documentation). Negative when some torque of `set` is beyond the rotors at any
    /// thrust. Source: extension of Theorem 2 (docs/airmode.md).
    pub fn shadow_margin(&self, set: &TorqueSet<T>) -> T {
        self.shadow_binding(set).margin
    }

    /// The largest `|τ_i|` [N m] the rotors realise on body axis `axis` (0, 1, 2: roll, pitch,
    /// yaw) alone, the other torques zero, at the best collective thrust for it: the shadow fit
    /// of the segment `±t e_i`, `t |d_i| ≤ w_k hi − w_l lo` for every ordered pair with
    /// `d = w_k c_l − w_l c_k`. Infinite when no pair's row differs on that axis.
    /// Panics if `axis > 2`.
    pub fn shadow_axis(&self, axis: usize) -> T {
        let (lo, hi) = self.range;
        let mut best = T::max_value().unwrap_or_else(T::one);
        for k in 0..4 {
            for l in 0..4 {
                let (wk, wl) = (self.collective[k], self.collective[l]);
                let d = (self.torque[l][axis] * wk - self.torque[k][axis] * wl).abs();
                if k != l && d > T::zero() {
                    best = best.min((wk * hi - wl * lo) / d);
                }
            }
        }
        best
    }

    /// `A(τ) = [max_k (lo − c_kᵀτ)/w_k, min_k (hi − c_kᵀτ)/w_k]` \[N\]: the collective thrusts
    /// at which the rotors realise `tau` [N m] (body axes) inside their range. Empty (first end
    /// above the second) when no thrust does.
    pub fn thrust_interval(&self, tau: &Vector3<T>) -> (T, T) {
        let (lo, hi) = self.range;
        let mut low = -T::max_value().unwrap_or_else(T::one);
        let mut high = T::max_value().unwrap_or_else(T::one);
        for k in 0..4 {
            let (w, c) = (self.collective[k], self.torque[k].dot(tau));
            low = low.max((lo - c) / w);
            high = high.min((hi - c) / w);
        }
        (low, high)
    }

    /// Airmode: the law's collective thrust `thrust` \[N\] moved into [`Self::thrust_interval`]
    /// of `tau` [N m] by as little as possible (unchanged when already inside). When the
    /// interval is empty (not with a set that passes [`Self::shadow_margin`]) its middle, the
    /// thrust that leaves the smallest excess on the worst rotor. NaN-free for finite inputs.
    #[inline]
    pub fn airmode_thrust(&self, thrust: T, tau: &Vector3<T>) -> T {
        let (low, high) = self.thrust_interval(tau);
        if low > high {
            (low + high) * crate::scalar::lit(0.5)
        } else if thrust < low {
            low
        } else if thrust > high {
            high
        } else {
            thrust
        }
    }

    /// The thrust interval \[N\] airmode keeps the law's thrust in when the law's own is
    /// `[t_lo, t_hi]` and its torque is in `set`: the lower end falls to at most
    /// `min_k (hi − h(−c_k))/w_k`'s least (where a torque of `set` forces the thrust down) and
    /// the upper end rises to at most `max_k (lo + h(c_k))/w_k` (where one forces it up).
    /// Source: [`Self::airmode_thrust`] and the support function of `set`.
    pub fn airmode_interval(&self, t_lo: T, t_hi: T, set: &TorqueSet<T>) -> (T, T) {
        let (lo, hi) = self.range;
        let (mut low, mut high) = (t_lo, t_hi);
        for k in 0..4 {
            let (w, h) = (self.collective[k], set.support(&self.torque[k]));
            low = low.min((hi - h) / w);
            high = high.max((lo + h) / w);
        }
        (low, high)
    }
}

#[cfg(test)]
mod tests;
