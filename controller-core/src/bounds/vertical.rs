//! Theorem 1 and the thrust-direction part of Lemma 1 with the vertical channel apart
//! (extension, docs/vertical-channel.md): the horizontal and vertical parts of `u` bounded
//! apart, and a vertical change of `u` charged to the thrust direction only through the tilt.

use nalgebra::{Vector2, Vector3};

use crate::integral::IntegralGains;
use crate::position::PositionGains;
use crate::reference::TrajectoryConstants;
use crate::scalar::{lit, Scalar};
use crate::vertical_channel::VerticalChannel;

// The vertical filters' `k_f,z`, `k_s,z` replace the horizontal ones in the vertical channel's
// differences (Lemma 1 axis by axis).

/// The bounds the vertical channel changes (module documentation), all in the units of
/// `crate::Bounds`'s fields of the same names.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct VerticalChain<T: Scalar> {
    /// `T_min = m(g − K_a3 − M_down − M_i,z)` \[N\].
    pub thrust_min: T,
    /// `T_max = m √((H + |M_i,xy| + K_a12)² + (g + K_a3 + M_i,z + M_up)²)` \[N\], `H` the
    /// horizontal reach of `ubar_p` (`√2 M_p` per component, `M_p` in norm).
    pub thrust_max: T,
    /// Bound on `|u̇|` [m/s³]: `√(U_u̇,xy² + U_u̇,z²)`.
    pub u_rate: T,
    /// Bound on `|ü|` [m/s⁴]: `√(U_ü,xy² + U_ü,z²)`.
    pub u_acceleration: T,
    /// `U_ρ̇ = U_u̇,xy/a + U_u̇,z κ` [1/s], `a = T_min/m`, `κ = sup|u_xy|/|u|²`.
    pub rho_d: T,
    /// Bound on `|ρ̈|` [1/s²]: `√(U_ρ̈⊥² + U_ρ̇⁴)`.
    pub rho_dd: T,
    /// Bound on the part of `ρ̈` across `ρ` [1/s²]: `U_ü,xy/a + U_ü,z κ + min(R², 2 R U_ρ̇)`,
    /// `R = U_u̇/a` the bound on `|u̇|/|u|`.
    pub rho_dd_projected: T,
    /// `L_ϖ = a/√(a² + (H + |M_i,xy| + K_a12)²)`.
    pub heading_projection_min: T,
}

/// The chain for the position gains `p` with the vertical channel `v`, on a vehicle of mass `m`
/// \[kg\] under `g` [m/s²], for the reference constants `k`, the integral action `integral` (its
/// level and the reachable-set bounds of `η̇_f`, `η̈_f` per axis) and Lemma 1's `U_l` of the
/// horizontal and the vertical filters (`overshoots`).
///
/// Why (docs/vertical-channel.md): `u = u_f + g e₃ + p̈_d (+ η_f)` has its horizontal part in the
/// disk of radius `H' = H + |M_i,xy| + K_a12` and its vertical part at least `a = g − K_a3 − M_down
/// − M_i,z > 0`; `ρ̇ = P_ρ u̇/|u|` with `|P_ρ(u̇_xy, 0)| ≤ |u̇_xy|` and `|P_ρ e₃| = |u_xy|/|u|`, so
/// `|ρ̇| ≤ |u̇_xy|/a + |u̇_z| κ`, `κ = sup |u_xy|/|u|² = H'/(H'² + a²)` (`1/(2a)` once `H' > a`); the
/// filter differences per channel are Lemma 1's with the channel's own range (the horizontal
/// `2H`, the vertical span `M_up + M_down`, centred: `U_l` times the span for `u_f − u_s`); and
/// `P_ρ ρ̈ = P_ρ ü/|u| − 2 a_r ρ̇` with `a_r = ρᵀu̇/|u|`, `a_r² + |ρ̇|² = |u̇|²/|u|² ≤ R²`.
pub(super) fn vertical_chain<T: Scalar>(
    (m, g): (T, T),
    p: &PositionGains<T>,
    v: &VerticalChannel<T>,
    k: &TrajectoryConstants<T>,
    integral: Option<&IntegralGains<T>>,
    (overshoot, overshoot_z): (T, T),
) -> VerticalChain<T> {
    let two = lit::<T>(2.0);
    let (kf, ks) = (p.kf, p.ks);
    let reach_xy = match p.saturation_shape {
        crate::PositionSaturation::Componentwise => two.sqrt(),
        crate::PositionSaturation::Norm => T::one(),
    };
    let h = reach_xy * p.saturation;
    let level = integral.map_or(Vector3::zeros(), |i| i.level);
    let (rate_int, acc_int) = integral.map_or((Vector3::zeros(), Vector3::zeros()), |i| {
        (i.filtered_rate_bound(), i.filtered_acceleration_bound())
    });
    let planar = |x: &Vector3<T>| Vector2::new(x.x, x.y).norm();
    let a = g - k.vertical_acceleration - v.down - level.z;
    let wide = h + planar(&level) + k.horizontal_acceleration;
    let top = g + k.vertical_acceleration + level.z + v.up;
    let span = v.span();
    let rate_xy = two * kf * overshoot * h + k.jerk + planar(&rate_int);
    let rate_z = v.kf * overshoot_z * span + k.jerk + rate_int.z.abs();
    let acc_xy = two * kf * h * (kf * overshoot + ks) + k.snap + planar(&acc_int);
    let acc_z = v.kf * span * (v.kf * overshoot_z + v.ks) + k.snap + acc_int.z.abs();
    let kappa = if wide <= a {
        wide / (wide * wide + a * a)
    } else {
        T::one() / (two * a)
    };
    let rho_d = rate_xy / a + rate_z * kappa;
    let u_rate = (rate_xy * rate_xy + rate_z * rate_z).sqrt();
    let radial = u_rate / a;
    let coupling = (radial * radial).min(two * radial * rho_d);
    let rho_dd_projected = acc_xy / a + acc_z * kappa + coupling;
    VerticalChain {
        thrust_min: m * a,
        thrust_max: m * (wide * wide + top * top).sqrt(),
        u_rate,
        u_acceleration: (acc_xy * acc_xy + acc_z * acc_z).sqrt(),
        rho_d,
        rho_dd: (rho_dd_projected * rho_dd_projected + rho_d * rho_d * rho_d * rho_d).sqrt(),
        rho_dd_projected,
        heading_projection_min: a / (a * a + wide * wide).sqrt(),
    }
}

#[cfg(test)]
mod tests;
