//! The boxes that enclose the confining set of the law's arguments.
//!
//! Per inertial component `i` (see [`super::filter_l1`] for `b₁`, `b₂`):
//! - `u = u_f + g e₃ + p̈_d` with `|u_f,i| ≤ M_p` (the filter is a positive system with unit DC
//!   gain, and the saturation box is invariant) and `|p̈_d,i| ≤ K_a12` (horizontal; the disc
//!   `|(p̈_d1, p̈_d2)| ≤ K_a12` lies in that square) or `≤ K_a3` (vertical):
//!   `u_i ∈ [−M_p − K_a12, M_p + K_a12]` (i = 1, 2), `u₃ ∈ [g − M_p − K_a3, g + M_p + K_a3]`;
//! - `u̇_i ∈ [−b₁ − K_j, b₁ + K_j]`, `ü_i ∈ [−b₂ − K_s, b₂ + K_s]` (`|p⁽³⁾_i| ≤ |p⁽³⁾| ≤ K_j`);
//! - heading `ν_d = (cos ψ, sin ψ)`, `ψ̇ ∈ [−K_ν̇, K_ν̇]` (`|ν̇_d| = |ψ̇|`),
//!   `ψ̈ ∈ [−K_ν̈, K_ν̈]` (`|ν̈_d|² = ψ̈² + ψ̇⁴ ≥ ψ̈²`).
//!
//! Treating the components and `u`, `u̇`, `ü` as independent drops correlations (they share the
//! filter states), so the product of the boxes is a superset of the confining set: sound.
//!
//! **Integral action** (extension, docs/integral-action.md; `controller_core::integral`): with
//! it on, `u = u_f + η_f + g e₃ + p̈_d` with, per component, `|η_f,i| ≤ M_i,i`,
//! `|η̇_f,i| ≤ b_i = min(2 k_η M_i,i, c R_i,i)` and `|η̈_f,i| ≤ k_η (b_i + R_i,i)` (the clamps
//! and the rate limit hold them there by construction over every state reachable from arming,
//! whatever the estimate's input: `controller_core::integral`'s reachable-set bound). Each box above widens by these terms
//! (a sum of independent boxes: sound), and `u₃ ≥ g − M_p − M_i,z − K_a3` must stay positive.
//! The two horizontal components take the larger of their terms, so that the boxes keep the
//! symmetries below (a superset: sound), and every `ü_i` the largest of the three, as without
//! the integral action.
//!
//! **Symmetries** (used to shrink the `ψ` and `ψ̇` ranges, proven in [`super`]'s documentation):
//! the box product is invariant under the dihedral group of the square acting on the horizontal
//! components (rotations by 90° about `e₃` and the reflections), which maps `ψ` to `ψ + k π/2`
//! and `ψ ↦ π/2 − ψ`, `ψ ↦ −ψ`; and under time reversal `(u̇, ψ̇) ↦ −(u̇, ψ̇)`. So
//! `ψ ∈ [0, π/4]` and `ψ̇ ∈ [0, K_ν̇]` suffice.

use controller_core::{FilterStart, Gains, ParameterError, TrajectoryConstants, Vehicle};

use super::filter_l1::rate_and_acceleration_bounds;
use super::interval::{next_up, Interval};

/// Per inertial component, what the integral action adds to the boxes of `u`, `u̇`, `ü`
/// (module documentation), rounded up; zeros with it off.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct IntegralTerms {
    /// `M_i,i` [m/s²].
    pub(super) level: [f64; 3],
    /// `b_i = min(2 k_η M_i,i, c R_i,i)` [m/s³], the reachable-set bound on `|η̇_f,i|`
    /// (`controller_core::IntegralGains::filtered_rate_bound`).
    pub(super) rate: [f64; 3],
    /// `k_η (b_i + R_i,i)` [m/s⁴].
    pub(super) acceleration: [f64; 3],
}

impl IntegralTerms {
    /// The terms of `gains`' integral action (zeros when it is off).
    pub(super) fn new(gains: &Gains<f64>) -> Self {
        let Some(i) = &gains.integral else {
            return Self {
                level: [0.0; 3],
                rate: [0.0; 3],
                acceleration: [0.0; 3],
            };
        };
        let p = Interval::point;
        // The reachable-set bound of controller_core::integral (never above 2 k_η M_i),
        // evaluated in floating point; 4 ulps cover its own rounding.
        let reachable = i.filtered_rate_bound();
        let rate = |c: usize| reachable[c] * (1.0 + 4.0 * f64::EPSILON);
        Self {
            level: core::array::from_fn(|c| i.level[c]),
            rate: core::array::from_fn(rate),
            acceleration: core::array::from_fn(|c| {
                (p(i.bandwidth) * (p(rate(c)) + p(i.rate[c]))).hi
            }),
        }
    }
}

/// Number of variables the search splits: `u` (3), `u̇` (3), `ψ`, `ψ̇`.
pub const SPLIT_DIM: usize = 8;

/// The boxes of the confining set (module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConfiningSet {
    /// Box of `(u₁, u₂, u₃, u̇₁, u̇₂, u̇₃, ψ, ψ̇)` [m/s², m/s³, rad, rad/s] after the symmetry
    /// reductions (`ψ ∈ [0, π/4]`, `ψ̇ ≥ 0`).
    pub split: [Interval; SPLIT_DIM],
    /// Half-width of the box of each `ü_i` [m/s⁴].
    pub u_ddot: f64,
    /// `K_ν̈`: half-width of the range of `ψ̈` [rad/s²].
    pub heading_acceleration: f64,
}

impl ConfiningSet {
    /// The boxes for one set-up.
    ///
    /// Errors: [`ParameterError`] for a non-positive or non-finite vehicle parameter or gain, a
    /// negative trajectory constant, or `M_p ≥ g − K_a3` (then `u₃` may vanish and `ω_d` is
    /// unbounded; same refusal as `certify`); with the integral action on,
    /// `M_p + M_i,z ≥ g − K_a3` (reported with `saturation = M_p + M_i,z`).
    pub fn new(
        vehicle: &Vehicle<f64>,
        gains: &Gains<f64>,
        constants: &TrajectoryConstants<f64>,
        filter_start: FilterStart,
    ) -> Result<Self, ParameterError> {
        vehicle.validate()?;
        gains.validate()?;
        constants.validate()?;
        let p = &gains.position;
        let (g, mp) = (vehicle.gravity, p.saturation);
        // The reference as the law applies it (the feedforward scale widens its constants).
        let k = &gains.law_constants(constants);
        let integral = IntegralTerms::new(gains);
        // `x + 0` is exact: adding only non-zero terms keeps the boxes (hence every bound)
        // bit for bit what they are without the integral action.
        let sum = |a: f64, b: f64| {
            if b == 0.0 {
                a
            } else {
                (Interval::point(a) + Interval::point(b)).hi
            }
        };
        let drop = if integral.level[2] == 0.0 {
            Interval::point(mp)
        } else {
            Interval::point(mp) + Interval::point(integral.level[2])
        };
        let floor = Interval::point(g) - drop - Interval::point(k.vertical_acceleration);
        if floor.lo <= 0.0 {
            return Err(ParameterError::SaturationTooLarge {
                saturation: drop.hi,
                limit: g - k.vertical_acceleration,
            });
        }
        let (b1, b2) = rate_and_acceleration_bounds(p.kf, p.ks, mp, filter_start);
        let horizontal = Interval::symmetric(sum(
            sum(mp, integral.level[0].max(integral.level[1])),
            k.horizontal_acceleration,
        ));
        let vertical = Interval::new(
            floor.lo,
            sum(sum(sum(g, mp), integral.level[2]), k.vertical_acceleration),
        );
        let horizontal_rate = integral.rate[0].max(integral.rate[1]);
        let rate = |extra: f64| Interval::symmetric(sum(sum(b1, extra), k.jerk));
        let acceleration = (0..3)
            .map(|i| sum(sum(b2, integral.acceleration[i]), k.snap))
            .fold(0.0, f64::max);
        Ok(Self {
            split: [
                horizontal,
                horizontal,
                vertical,
                rate(horizontal_rate),
                rate(horizontal_rate),
                rate(integral.rate[2]),
                Interval::new(0.0, next_up(core::f64::consts::FRAC_PI_4)),
                Interval::new(0.0, k.heading_rate),
            ],
            u_ddot: acceleration,
            heading_acceleration: k.heading_acceleration,
        })
    }
}
