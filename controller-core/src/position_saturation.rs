//! The shape of the position feedback's saturation `σ_p`: the paper's componentwise one, or a
//! norm (radial) one (an extension; docs/position-saturation.md).
//!
//! The paper saturates each inertial component of `k_p z₁ + k_v z₂` on its own (Definition 1,
//! `σ(s) = M tanh(s/M)` in Section VI), so `ubar_p` lies in the cube `M_p 𝔹³_∞` and every
//! bound that needs `|ubar_p|` pays `√3 M_p` (Theorem 1's `T_max`, Lemma 1's `U_u̇`, `U_ü`) and
//! `√2 M_p` for its horizontal part (Lemma 1's `L_ϖ`), although the level `M_p` the vehicle
//! brakes with on one axis is only `M_p`.
//!
//! The norm shape is `σ_p(y) = M_p y / sqrt(M_p² + |y|²)`, the radial saturation the paper
//! already uses for `s_ϑ` and `s_ω` in Section V. It keeps the direction of `y` and `|σ_p| <
//! M_p`, so the same bounds hold with `M_p` in place of `√3 M_p` and of `√2 M_p`: for the
//! same certified thrust interval and attitude references, `M_p` can be up to `√3` times
//! larger, on every axis at once.
//!
//! **Why Theorem 1's proof still holds** (docs/position-saturation.md has it in full):
//! `σ_p = ∇Φ` with `Φ(y) = M_p sqrt(M_p² + |y|²)`, which is strictly convex, so
//! - the integrals `∫₀^y σ_pᵀ dμ` of `V_p` are path independent (`Φ(y) − Φ(0)`), positive
//!   definite and radially unbounded;
//! - `σ_p` is strictly monotone, `(σ_p(a) − σ_p(b))ᵀ(a − b) > 0` for `a ≠ b`, which is the only
//!   property the sign of `V̇₁`'s cross term uses;
//! - on the ball `|y| ≤ α` (convex, so it holds the segment between two of its points) the
//!   Hessian of `Φ` is at least `σ'_p(α) I` with `σ'_p(α) = M_p³/(M_p² + α²)^{3/2}` (its radial
//!   eigenvalue), which gives eq:P2fromDef, and `|σ_p(y)| ≥ σ_p(α)/α |y|` gives eq:P1fromDef.
//!
//! The linearisation at the origin is the identity, as for the componentwise shape, so every
//! local analysis (the integral action's Liénard–Chipart conditions) is unchanged.

use nalgebra::Vector3;

use crate::saturation::{radial_saturation, tanh_saturation};
use crate::scalar::{lit, Scalar};

/// Shape of the position feedback's saturation `σ_p` of `ubar_p = −σ_p(k_p z₁ + k_v z₂)`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PositionSaturation {
    /// The paper's: `M_p tanh(y_i/M_p)` on each inertial component (Definition 1, Section VI);
    /// `ubar_p` in the cube `M_p 𝔹³_∞`.
    #[default]
    Componentwise,
    /// `M_p y / sqrt(M_p² + |y|²)`: `ubar_p` in the ball `M_p 𝔹³`, direction kept (extension,
    /// docs/position-saturation.md).
    Norm,
}

impl PositionSaturation {
    /// `σ_p(y)` with level `M_p = level` (> 0, checked by the gains' validation).
    ///
    /// Shape 3-vector in, 3-vector out, inertial, same unit (m/s² for the position loop).
    /// Source: Definition 1 and Section VI (componentwise); Section V's radial saturation
    /// (norm, extension).
    #[inline]
    pub fn apply<T: Scalar>(self, y: &Vector3<T>, level: T) -> Vector3<T> {
        match self {
            Self::Componentwise => tanh_saturation(y, level),
            Self::Norm => radial_saturation(y, level),
        }
    }

    /// The size of `v` in this shape's norm: the largest component for the componentwise shape,
    /// the Euclidean norm for the norm shape (same unit as `v`). `σ_p` keeps it below `M_p`.
    #[inline]
    pub fn size<T: Scalar>(self, v: &Vector3<T>) -> T {
        match self {
            Self::Componentwise => v.amax(),
            Self::Norm => v.norm(),
        }
    }

    /// `sup |σ_p| / M_p`: `√3` (the cube's corner) or `1`. Theorem 1's `T_max` and Lemma 1's
    /// `U_u̇`, `U_ü` scale with it (dimensionless).
    #[inline]
    pub fn norm_factor<T: Scalar>(self) -> T {
        match self {
            Self::Componentwise => lit::<T>(3.0).sqrt(),
            Self::Norm => T::one(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use proptest::prelude::*;

    fn v3(r: f64) -> impl Strategy<Value = Vector3<f64>> {
        (-r..r, -r..r, -r..r).prop_map(|(a, b, c)| Vector3::new(a, b, c))
    }

    /// `Φ(y) = M sqrt(M² + |y|²)`, the potential whose gradient is the norm shape.
    fn potential(y: &Vector3<f64>, m: f64) -> f64 {
        m * (m * m + y.norm_squared()).sqrt()
    }

    proptest! {
        /// Given any argument, when the norm shape saturates it, then the result is parallel to
        /// it, no longer than M_p (equal only where rounding saturates) and no longer than the
        /// argument; the componentwise shape keeps
        /// every component below M_p and can exceed M_p in norm (up to √3 M_p).
        #[test]
        fn norm_shape_stays_in_the_ball(y in v3(100.0), m in 0.05..10.0f64) {
            let s = PositionSaturation::Norm.apply(&y, m);
            prop_assert!(s.norm() <= m);
            prop_assert!(s.norm() <= y.norm() * (1.0 + 1e-15));
            prop_assert!((s.cross(&y)).norm() <= 1e-9 * (1.0 + y.norm() * s.norm()));
            prop_assert!(s.dot(&y) >= 0.0);
            let c = PositionSaturation::Componentwise.apply(&y, m);
            prop_assert!(PositionSaturation::Componentwise.size(&c) <= m);
            prop_assert!(c.norm() <= PositionSaturation::Componentwise.norm_factor::<f64>() * m * (1.0 + 1e-15));
        }

        /// Strict monotonicity, the property Theorem 1's V̇₁ cross term uses:
        /// (σ(a) − σ(b))ᵀ(a − b) > 0, and on the ball |y| ≤ α the slope bound of eq:P2fromDef,
        /// |σ(a) − σ(b)| ≥ M³/(M² + α²)^{3/2} |a − b|.
        #[test]
        fn norm_shape_is_strictly_monotone_with_the_radial_slope(
            a in v3(20.0), b in v3(20.0), m in 0.1..5.0f64,
        ) {
            prop_assume!((a - b).norm() > 1e-6);
            let n = PositionSaturation::Norm;
            let d = n.apply(&a, m) - n.apply(&b, m);
            prop_assert!(d.dot(&(a - b)) > 0.0);
            let alpha = a.norm().max(b.norm());
            let slope = m.powi(3) / (m * m + alpha * alpha).powf(1.5);
            prop_assert!(d.norm() >= slope * (a - b).norm() * (1.0 - 1e-9));
        }

        /// The norm shape is the gradient of Φ (so V_p's integral is path independent): a
        /// central difference of Φ matches it.
        #[test]
        fn norm_shape_is_a_gradient(y in v3(10.0), m in 0.1..5.0f64) {
            let h = 1e-6;
            let s = PositionSaturation::Norm.apply(&y, m);
            for i in 0..3 {
                let mut e = Vector3::zeros();
                e[i] = h;
                let fd = (potential(&(y + e), m) - potential(&(y - e), m)) / (2.0 * h);
                prop_assert!((fd - s[i]).abs() <= 1e-6 * (1.0 + s[i].abs()));
            }
        }
    }

    #[test]
    fn both_shapes_have_unit_slope_at_the_origin() {
        let tiny = Vector3::new(1e-9, -2e-9, 3e-9);
        for shape in [PositionSaturation::Componentwise, PositionSaturation::Norm] {
            assert_relative_eq!(shape.apply(&tiny, 2.0), tiny, max_relative = 1e-12);
        }
    }

    #[test]
    fn the_default_is_the_papers_shape() {
        assert_eq!(
            PositionSaturation::default(),
            PositionSaturation::Componentwise
        );
    }
}
