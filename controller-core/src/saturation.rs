//! Saturation functions of the paper (Definition 1 and the radial saturations of Section V).
//!
//! Two shapes are used:
//! - componentwise `σ(s) = M tanh(s/M)` (Definition 1, Section VI), for the position feedback
//!   `ubar_p`: each component lies in `(-M, M)`, so the vector lies in `√3 M 𝔹³`;
//! - radial `s(x) = M x / sqrt(M² + |x|²)` (Section V, `s_θ`, `s_ω`): the vector norm lies in
//!   `[0, M)` and the direction of `x` is kept.

use nalgebra::Vector3;

use crate::scalar::Scalar;

/// Componentwise smooth saturation `M tanh(s/M)` of Definition 1.
///
/// Input `s` in any unit; output in the same unit with every component in `(-M, M)`.
/// `level` is `M > 0` (not checked here: the controller validates its gains).
/// Source: Definition 1; the choice `σ(s) = M tanh(s/M)` is Section VI's.
#[inline]
pub fn tanh_saturation<T: Scalar>(s: &Vector3<T>, level: T) -> Vector3<T> {
    s.map(|si| level * (si / level).tanh())
}

/// Slope of [`tanh_saturation`] at `s` (scalar): `σ'(s) = 1 - tanh²(s/M)`, in `(0, 1]`.
///
/// Used by the feasibility analysis (Theorem 3's `σ'(α₁)`) and by property tests.
/// Source: Definition 1 property (4).
#[inline]
pub fn tanh_saturation_slope<T: Scalar>(s: T, level: T) -> T {
    let t = (s / level).tanh();
    T::one() - t * t
}

/// Radial saturation `s(x) = M x / sqrt(M² + |x|²)` of Section V.
///
/// Shape 3-vector in, 3-vector out, same unit; `|s(x)| < M` and `s(x)` is parallel to `x`.
/// The caller applies its gain before the call (`s_θ(k_θ ϑ)` is `radial_saturation(k_θ ϑ, M_θ)`),
/// which is the reading of Section V used throughout this crate.
/// Source: Section V, definitions of `s_ϑ` and `s_ω`.
#[inline]
pub fn radial_saturation<T: Scalar>(x: &Vector3<T>, level: T) -> Vector3<T> {
    x * (level / (level * level + x.norm_squared()).sqrt_ieee())
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use proptest::prelude::*;

    fn v3() -> impl Strategy<Value = Vector3<f64>> {
        (-50.0..50.0f64, -50.0..50.0f64, -50.0..50.0f64).prop_map(|(a, b, c)| Vector3::new(a, b, c))
    }

    proptest! {
        /// Definition 1 for `M tanh(s/M)`: odd, |σ| < M, strictly increasing with slope in (0, 1],
        /// σ(s) s > 0 for s ≠ 0, and σ ≈ s near 0 (unit slope at the origin).
        #[test]
        fn tanh_saturation_is_odd_bounded_monotone(s in v3(), ds in 1e-6..10.0f64, m in 0.1..10.0f64) {
            let up = s.add_scalar(ds);
            let (a, b) = (tanh_saturation(&s, m), tanh_saturation(&up, m));
            assert_relative_eq!(tanh_saturation(&-s, m), -a, epsilon = 1e-15);
            prop_assert!(a.amax() <= m && b.amax() <= m);
            for i in 0..3 {
                // Strict increase up to rounding: in the flat tails tanh rounds to ±1.
                prop_assert!(b[i] >= a[i]);
                prop_assert!(b[i] - a[i] <= ds + 1e-12, "slope above 1");
                if s[i] != 0.0 {
                    prop_assert!(a[i] * s[i] > 0.0 || a[i] == 0.0);
                }
                let slope = tanh_saturation_slope(s[i], m);
                prop_assert!(slope > 0.0 || s[i].abs() > 10.0 * m);
                prop_assert!(slope <= 1.0);
            }
            let tiny = s * (1e-9 * m / (1.0 + s.norm()));
            assert_relative_eq!(tanh_saturation(&tiny, m), tiny, max_relative = 1e-12);
        }

        /// The radial saturation: odd, |s(x)| < M, parallel to x, and |s(x)| strictly increasing
        /// in |x| with slope ≤ 1; s(x) ≈ x near 0.
        #[test]
        fn radial_saturation_is_odd_bounded_monotone(x in v3(), grow in 1.0001..10.0f64, m in 0.01..10.0f64) {
            let a = radial_saturation(&x, m);
            assert_relative_eq!(radial_saturation(&-x, m), -a, epsilon = 1e-15);
            prop_assert!(a.norm() < m);
            prop_assert!(a.cross(&x).norm() <= 1e-12 * (1.0 + x.norm() * a.norm()));
            prop_assert!(a.dot(&x) >= 0.0);
            let b = radial_saturation(&(x * grow), m);
            if x.norm() > 0.0 {
                prop_assert!(b.norm() > a.norm());
                prop_assert!(b.norm() - a.norm() <= (grow - 1.0) * x.norm() + 1e-12);
            }
            let tiny = x * (1e-9 * m / (1.0 + x.norm()));
            assert_relative_eq!(radial_saturation(&tiny, m), tiny, max_relative = 1e-12);
        }
    }
}
