//! The vertical channel's decision variables (docs/vertical-channel.md): its braking and
//! descent levels and its filters, as ratios to the horizontal ones.

use super::interval::{unit_in, value_in, Interval};
use super::VERTICAL_DIMENSION;

/// The vertical channel's levels as ratios to the horizontal `M_p` (docs/vertical-channel.md).
///
/// | # | variable | range |
/// |---|----------|-------|
/// | 0 | `M_up / M_p` | 1 to 8 (log) |
/// | 1 | `M_down / M_p` | 0.1 to 1 (log) |
/// | 2 | `k_f,z / k_f` | 0.5 to 10 (log) |
/// | 3 | `k_s,z / k_f,z` | 1.5 to 12 (log) |
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct VerticalChoices {
    /// `M_up / M_p`.
    pub up_ratio: f64,
    /// `M_down / M_p`.
    pub down_ratio: f64,
    /// `k_f,z / k_f`.
    pub kf_ratio: f64,
    /// `k_s,z / k_f,z`.
    pub ks_ratio: f64,
}

pub(super) const VERTICAL_RANGES: [Interval; VERTICAL_DIMENSION] = [
    (1.0, 8.0, true),
    (0.1, 1.0, true),
    (0.5, 10.0, true),
    (1.5, 12.0, true),
];

/// The names of [`VERTICAL_RANGES`]' variables, as reports print them.
pub(super) const VERTICAL_NAMES: [&str; VERTICAL_DIMENSION] =
    ["M_up / M_p", "M_down / M_p", "k_f,z / k_f", "k_s,z / k_f,z"];

impl VerticalChoices {
    /// The initial guess: brake at three times the horizontal level, descend at half of it,
    /// vertical filters twice as fast as the horizontal ones.
    pub fn initial_guess() -> Self {
        Self {
            up_ratio: 3.0,
            down_ratio: 0.5,
            kf_ratio: 2.0,
            ks_ratio: 3.0,
        }
    }

    pub(super) fn from_unit(x: &[f64]) -> Self {
        let v = |i: usize| value_in(VERTICAL_RANGES[i], x.get(i).copied().unwrap_or(0.5));
        Self {
            up_ratio: v(0),
            down_ratio: v(1),
            kf_ratio: v(2),
            ks_ratio: v(3),
        }
    }

    pub(super) fn to_unit(self) -> [f64; VERTICAL_DIMENSION] {
        let values = [self.up_ratio, self.down_ratio, self.kf_ratio, self.ks_ratio];
        core::array::from_fn(|i| unit_in(VERTICAL_RANGES[i], values[i]))
    }
}
