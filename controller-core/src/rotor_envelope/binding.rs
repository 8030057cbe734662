//! Which rotor pair binds the shadow fit, and along which direction: the pair whose slack sets
//! [`RotorEnvelope::shadow_margin`], so that a report can split that pair's budget among the
//! certified set's parts ([`crate::torque_set::SupportParts`]).

use nalgebra::Vector3;

use super::RotorEnvelope;
use crate::scalar::Scalar;
use crate::torque_set::TorqueSet;

/// The ordered rotor pair `(k, l)` that attains the shadow fit's least slack
/// (docs/airmode.md): `h_S(d) ≤ w_k hi − w_l lo` with `d = w_k c_l − w_l c_k`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadowBinding<T: Scalar> {
    /// The pair's rotor indices `(k, l)`, 0-based in the mixer's order, `k ≠ l`.
    pub rotors: (usize, usize),
    /// The direction `d = w_k c_l − w_l c_k` [1/m], body axes: `dᵀτ` is what the torque `τ`
    /// [N m] asks of the pair's difference.
    pub direction: Vector3<T>,
    /// `w_k hi − w_l lo` \[N\]: the most `dᵀτ` can be with both rotors in their range.
    pub capacity: T,
    /// The margin, as [`RotorEnvelope::shadow_margin`]: `(capacity − h_S(d)) / ((w_k + w_l)
    /// (hi − lo))`, a fraction of the rotor range (negative when the set does not fit).
    pub margin: T,
}

impl<T: Scalar> RotorEnvelope<T> {
    /// The pair that binds the shadow fit of `set` ([`ShadowBinding`]): the least slack over
    /// the ordered pairs, the first in the order `(0, 1), (0, 2), …` on a tie. No errors.
    /// Source: extension of Theorem 2 (docs/airmode.md).
    pub fn shadow_binding(&self, set: &TorqueSet<T>) -> ShadowBinding<T> {
        let (lo, hi) = self.range;
        let mut binding = ShadowBinding {
            rotors: (0, 1),
            direction: Vector3::zeros(),
            capacity: T::zero(),
            margin: T::max_value().unwrap_or_else(T::one),
        };
        for k in 0..4 {
            for l in 0..4 {
                if k == l {
                    continue;
                }
                let (wk, wl) = (self.collective[k], self.collective[l]);
                let d = self.torque[l] * wk - self.torque[k] * wl;
                let capacity = wk * hi - wl * lo;
                let margin = (capacity - set.support(&d)) / ((wk + wl) * (hi - lo));
                if margin < binding.margin {
                    binding = ShadowBinding {
                        rotors: (k, l),
                        direction: d,
                        capacity,
                        margin,
                    };
                }
            }
        }
        binding
    }
}

#[cfg(test)]
mod tests;
