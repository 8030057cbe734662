//! The vertical channel of the position feedback apart from the horizontal one: an asymmetric
//! saturation with an upward level for braking and a smaller downward one, and its own filter
//! bandwidths (an extension; docs/vertical-channel.md).
//!
//! With it, `ubar_p = −σ_p(k_p z₁ + k_v z₂)` keeps the shape of `σ_p` on the horizontal pair
//! `(x, y)` with the level `M_p` (per component, or the 2-D norm with the norm shape), and its
//! vertical component is `−σ_z(y_z)` with
//!
//! `σ_z(y) = M_down tanh(y/M_down)` for `y ≥ 0`, `M_up tanh(y/M_up)` for `y < 0`,
//!
//! so `ubar_p,z ∈ (−M_down, M_up)`; the vertical filters `u̇_f,z = −k_f,z(u_f,z − u_s,z)`,
//! `u̇_s,z = −k_s,z(u_s,z − ubar_p,z)` have their own bandwidths, and the z-coordinates of the
//! vertical axis use them (eq:Zcoordinates per axis: the double integrator `z̈₁ = ubar_p` holds
//! axis by axis). Theorem 1's interval follows the two levels apart:
//! `T_min = m(g − K_a3 − M_down)` needs only the downward one, so a large braking level `M_up`
//! does not lower the thrust floor, does not shrink `|u|`, and so does not raise the
//! thrust-direction rates Lemma 1 divides by `T_min/m`; a vertical change of `u` turns the thrust
//! direction only through the tilt, `|P_ρ e₃| = |u_xy|/|u|` (docs/vertical-channel.md).
//!
//! **Theorem 1's proof still holds.** `σ_p = ∇(Φ_xy(y_xy) + Φ_z(y_z))` with `Φ_xy` the
//! horizontal shape's convex potential and `Φ_z(y) = ∫₀^y σ_z`, convex (`σ_z` strictly increasing),
//! so `σ_p` is the gradient of a strictly convex function: `V_p`'s integrals are path
//! independent and positive definite, the cross term of `V̇₁` keeps its sign (strict
//! monotonicity), and on the box `|y_i| ≤ α` the slopes are at least the smaller of the two
//! sides' `σ'(α)` (eq:P2fromDef) and `|σ(y)| ≥ min(σ_up(α), σ_down(α))/α |y|` (eq:P1fromDef).
//! `σ_z` is twice continuously differentiable (the two `tanh` agree to second order at 0), and
//! its linearisation at the origin is the identity, as the paper's.

use nalgebra::Vector3;

use crate::parameter_error::{positive, ParameterError};
use crate::scalar::Scalar;

/// The vertical channel's saturation levels and filter bandwidths (extension,
/// docs/vertical-channel.md).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VerticalChannel<T: Scalar> {
    /// `M_up` [m/s²]: the largest upward `ubar_p,z` (braking a fall).
    pub up: T,
    /// `M_down` [m/s²]: the largest downward `ubar_p,z`; `M_down < g − K_a3` (with the integral
    /// action, `M_down + M_i,z < g − K_a3`) keeps the thrust floor positive.
    pub down: T,
    /// `k_f,z` [1/s]: bandwidth of the vertical output filter.
    pub kf: T,
    /// `k_s,z` [1/s]: bandwidth of the vertical inner filter.
    pub ks: T,
}

impl<T: Scalar> VerticalChannel<T> {
    /// Checks both levels and both bandwidths finite and `> 0`.
    /// Errors: [`ParameterError::NotPositive`] naming `"M_up"`, `"M_down"`, `"k_f,z"` or
    /// `"k_s,z"`.
    pub fn validate(&self) -> Result<(), ParameterError> {
        positive("M_up", self.up)?;
        positive("M_down", self.down)?;
        positive("k_f,z", self.kf)?;
        positive("k_s,z", self.ks)
    }

    /// `ubar_p,z = −σ_z(y)` [m/s²] for the vertical argument `y = k_p z₁,z + k_v z₂,z` [m/s²]:
    /// in `(−M_down, M_up)`. Source: extension (module documentation).
    #[inline]
    pub fn feedback(&self, y: T) -> T {
        if y >= T::zero() {
            -self.down * (y / self.down).tanh()
        } else {
            -self.up * (y / self.up).tanh()
        }
    }

    /// Whether the vertical component `z` [m/s²] lies in `[−M_down, M_up]` (where the filters
    /// keep `u_f,z` and `u_s,z`).
    #[inline]
    pub fn contains(&self, z: T) -> bool {
        z >= -self.down && z <= self.up
    }

    /// `z` [m/s²] clamped into `[−M_down, M_up]`.
    #[inline]
    pub fn clamp(&self, z: T) -> T {
        z.max(-self.down).min(self.up)
    }

    /// The span `M_up + M_down` [m/s²] of `ubar_p,z` (what Lemma 1's filter differences take).
    #[inline]
    pub fn span(&self) -> T {
        self.up + self.down
    }
}

/// The horizontal part `(v_x, v_y, 0)` of `v`.
#[inline]
pub(crate) fn horizontal<T: Scalar>(v: &Vector3<T>) -> Vector3<T> {
    Vector3::new(v.x, v.y, T::zero())
}

#[cfg(test)]
mod tests;
