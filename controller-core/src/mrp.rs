//! Modified Rodrigues parameters (MRP): quaternion ↔ MRP, shadow MRP, kinematics, rotation.
//!
//! Conventions (fixed for the whole crate): quaternions are Hamilton, scalar first in the
//! paper's notation `q = (q₀, q₁)`, and describe the body-to-inertial rotation
//! `R(q) = I + 2q₀[q₁]ₓ + 2[q₁]ₓ²` (Section II). nalgebra stores them as `(i, j, k, w)`;
//! `w` is `q₀`.
//!
//! Note on eq:rotationmatrixMRP: the paper prints
//! `R_ϑ(ϑ) = I + (8[ϑ]ₓ² − 4(1−|ϑ|²)[ϑ]ₓ)/(1+|ϑ|²)²`, which is Schaub and Junkins' direction
//! cosine matrix `[BN]` (inertial to body), i.e. the *transpose* of `R(q)` for `ϑ = φ(q)`.
//! With the paper's own `R(q)` and kinematics `ϑ̇ = T(ϑ)ω` (both body-to-inertial, body-frame
//! `ω`), the consistent map has `+4(1−|ϑ|²)[ϑ]ₓ`; [`rotation_from_mrp`] implements that, and a
//! test pins `rotation_from_mrp(φ(q)) = R(q)`. The control law only uses `ϑ = φ(q)` and `T(ϑ)`,
//! which are consistent, so it is unaffected.

use nalgebra::{Matrix3, Quaternion, Vector3};

use crate::scalar::{lit, norm, Scalar};

/// The MRP `ϑ = φ(q) = q₁ / (1 + q₀)` of a unit quaternion (stereographic projection).
///
/// Input: unit quaternion (dimensionless). Output: 3-vector, dimensionless, same frame as `q₁`.
/// Returns `None` at `q = (−1, 0, 0, 0)`, where `φ` maps to the point at infinity.
/// Source: Section II, definition of `φ`.
#[inline]
pub fn mrp_from_quaternion<T: Scalar>(q: &Quaternion<T>) -> Option<Vector3<T>> {
    let den = T::one() + q.w;
    if den <= T::zero() {
        return None;
    }
    Some(q.vector() / den)
}

/// The unit quaternion of an MRP: `q₀ = (1 − |ϑ|²)/(1 + |ϑ|²)`, `q₁ = 2ϑ/(1 + |ϑ|²)`.
///
/// Inverse of [`mrp_from_quaternion`] (returns the representative with `φ(q) = ϑ`).
/// Source: Schaub and Junkins, Analytical Mechanics of Space Systems, MRP–EP relations.
#[inline]
pub fn quaternion_from_mrp<T: Scalar>(mrp: &Vector3<T>) -> Quaternion<T> {
    let n2 = mrp.norm_squared();
    let den = T::one() + n2;
    let v = mrp * (lit::<T>(2.0) / den);
    Quaternion::new((T::one() - n2) / den, v.x, v.y, v.z)
}

/// The shadow MRP `ϑˢ = Υ(ϑ) = −ϑ / |ϑ|²`, which describes the same rotation as `ϑ`.
///
/// Input/output: 3-vectors, dimensionless. Returns `None` for `ϑ = 0`, whose shadow is the
/// point at infinity. Source: Section II, map `Υ`.
#[inline]
pub fn shadow_mrp<T: Scalar>(mrp: &Vector3<T>) -> Option<Vector3<T>> {
    let n2 = mrp.norm_squared();
    if n2 <= T::zero() {
        return None;
    }
    Some(-mrp / n2)
}

/// The MRP kinematics matrix `T(ϑ) = ((1 − |ϑ|²)I + 2[ϑ]ₓ + 2ϑϑᵀ)/4`, with `ϑ̇ = T(ϑ)ω`.
///
/// Input: MRP (dimensionless); output: 3×3 matrix mapping the body-frame angular velocity
/// [rad/s] to `ϑ̇` [1/s]. Source: Section II, MRP kinematics (Schaub and Junkins).
#[inline]
pub fn mrp_kinematics<T: Scalar>(mrp: &Vector3<T>) -> Matrix3<T> {
    let quarter = lit::<T>(0.25);
    let two = lit::<T>(2.0);
    (Matrix3::identity() * (T::one() - mrp.norm_squared())
        + mrp.cross_matrix() * two
        + mrp * mrp.transpose() * two)
        * quarter
}

/// The body-to-inertial rotation matrix of an MRP, consistent with `R(q)` for `ϑ = φ(q)`.
///
/// `R = I + (8[ϑ]ₓ² + 4(1 − |ϑ|²)[ϑ]ₓ) / (1 + |ϑ|²)²`. Input: MRP (dimensionless); output
/// 3×3 rotation matrix (body to inertial). `R(ϑ) = R(Υ(ϑ))`.
/// Source: eq:rotationmatrixMRP, with the sign of the `[ϑ]ₓ` term made consistent with the
/// paper's `R(q)` (see the module documentation).
#[inline]
pub fn rotation_from_mrp<T: Scalar>(mrp: &Vector3<T>) -> Matrix3<T> {
    let n2 = mrp.norm_squared();
    let s = mrp.cross_matrix();
    let den = (T::one() + n2) * (T::one() + n2);
    Matrix3::identity() + (s * s * lit::<T>(8.0) + s * (lit::<T>(4.0) * (T::one() - n2))) / den
}

/// The rotation matrix `R(q) = I + 2q₀[q₁]ₓ + 2[q₁]ₓ²` of a unit quaternion (body to inertial).
///
/// Source: Section II, map `𝓡` (Mayhew, Sanfelice and Teel 2013, eq. 5).
#[inline]
pub fn rotation_from_quaternion<T: Scalar>(q: &Quaternion<T>) -> Matrix3<T> {
    let s = q.vector().into_owned().cross_matrix();
    let two = lit::<T>(2.0);
    Matrix3::identity() + s * (two * q.w) + s * s * two
}

/// One unit quaternion of a rotation matrix (either sign may come out; callers choose the sign).
///
/// Input: a 3×3 rotation matrix (assumed on SO(3) to rounding). Output: unit quaternion with
/// `R(q) = R`. Uses the numerically robust largest-pivot extraction (Shepperd's method).
/// Source: `𝒬` of Section II; Shepperd (1978), "Quaternion from rotation matrix".
#[inline]
pub fn quaternion_from_rotation<T: Scalar>(r: &Matrix3<T>) -> Quaternion<T> {
    let quarter = lit::<T>(0.25);
    let half = lit::<T>(0.5);
    let trace = r[(0, 0)] + r[(1, 1)] + r[(2, 2)];
    let q = if trace >= r[(0, 0)] && trace >= r[(1, 1)] && trace >= r[(2, 2)] {
        let w = (T::one() + trace).sqrt_ieee() * half;
        let k = quarter / w;
        Quaternion::new(
            w,
            (r[(2, 1)] - r[(1, 2)]) * k,
            (r[(0, 2)] - r[(2, 0)]) * k,
            (r[(1, 0)] - r[(0, 1)]) * k,
        )
    } else if r[(0, 0)] >= r[(1, 1)] && r[(0, 0)] >= r[(2, 2)] {
        let x = (T::one() + r[(0, 0)] - r[(1, 1)] - r[(2, 2)]).sqrt_ieee() * half;
        let k = quarter / x;
        Quaternion::new(
            (r[(2, 1)] - r[(1, 2)]) * k,
            x,
            (r[(0, 1)] + r[(1, 0)]) * k,
            (r[(0, 2)] + r[(2, 0)]) * k,
        )
    } else if r[(1, 1)] >= r[(2, 2)] {
        let y = (T::one() - r[(0, 0)] + r[(1, 1)] - r[(2, 2)]).sqrt_ieee() * half;
        let k = quarter / y;
        Quaternion::new(
            (r[(0, 2)] - r[(2, 0)]) * k,
            (r[(0, 1)] + r[(1, 0)]) * k,
            y,
            (r[(1, 2)] + r[(2, 1)]) * k,
        )
    } else {
        let z = (T::one() - r[(0, 0)] - r[(1, 1)] + r[(2, 2)]).sqrt_ieee() * half;
        let k = quarter / z;
        Quaternion::new(
            (r[(1, 0)] - r[(0, 1)]) * k,
            (r[(0, 2)] + r[(2, 0)]) * k,
            (r[(1, 2)] + r[(2, 1)]) * k,
            z,
        )
    };
    // Rounding in R leaves |q| a few ulp off 1; φ and the inner products assume unit norm.
    q / norm(&q.coords)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use nalgebra::{UnitQuaternion, Vector3};
    use proptest::prelude::*;

    fn unit_quaternion() -> impl Strategy<Value = Quaternion<f64>> {
        // Normalised Gaussian 4-vectors are uniform on S³; a 4-cube is enough for coverage here.
        (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64)
            .prop_filter("not near zero", |(a, b, c, d)| {
                a * a + b * b + c * c + d * d > 1e-3
            })
            .prop_map(|(a, b, c, d)| {
                let q = Quaternion::new(a, b, c, d);
                q / q.norm()
            })
    }

    proptest! {
        #[test]
        fn mrp_and_shadow_give_the_same_rotation(q in unit_quaternion()) {
            let r = rotation_from_quaternion(&q);
            if let Some(m) = mrp_from_quaternion(&q) {
                assert_relative_eq!(rotation_from_mrp(&m), r, epsilon = 1e-9);
                if let Some(s) = shadow_mrp(&m) {
                    assert_relative_eq!(rotation_from_mrp(&s), r, epsilon = 1e-9);
                    // The shadow is φ(−q), the other sign of the same rotation.
                    let minus = mrp_from_quaternion(&(-q)).unwrap();
                    assert_relative_eq!(s, minus, epsilon = 1e-9 * (1.0 + s.norm()));
                }
            }
        }

        #[test]
        fn rotation_matches_nalgebra_and_round_trips(q in unit_quaternion()) {
            let r = rotation_from_quaternion(&q);
            let nq = UnitQuaternion::from_quaternion(q);
            assert_relative_eq!(r, nq.to_rotation_matrix().into_inner(), epsilon = 1e-12);
            let back = quaternion_from_rotation(&r);
            // Same rotation up to the sign of q.
            prop_assert!((back.dot(&q).abs() - 1.0).abs() < 1e-12);
            assert_relative_eq!((r.transpose() * r), Matrix3::identity(), epsilon = 1e-12);
        }

        #[test]
        fn quaternion_mrp_round_trip(q in unit_quaternion()) {
            if let Some(m) = mrp_from_quaternion(&q) {
                let back = quaternion_from_mrp(&m);
                assert_relative_eq!(back, q, epsilon = 1e-9 * (1.0 + m.norm_squared()));
            }
        }

        #[test]
        fn kinematics_matches_quaternion_rate(q in unit_quaternion(),
            wx in -5.0..5.0f64, wy in -5.0..5.0f64, wz in -5.0..5.0f64) {
            // Differentiate φ(q(t)) numerically along q̇ = ½ q ⊗ (0, ω) and compare with T(ϑ)ω.
            prop_assume!(q.w > -0.5);
            let w = Vector3::new(wx, wy, wz);
            let h = 1e-6;
            let step = |s: f64| {
                let dq = q * Quaternion::from_parts(0.0, w) * 0.5;
                let qs = q + dq * s;
                mrp_from_quaternion(&(qs / qs.norm())).unwrap()
            };
            let numeric = (step(h) - step(-h)) / (2.0 * h);
            let m = mrp_from_quaternion(&q).unwrap();
            assert_relative_eq!(mrp_kinematics(&m) * w, numeric, epsilon = 1e-6 * (1.0 + numeric.norm()));
        }
    }

    #[test]
    fn paper_printed_mrp_matrix_is_the_transpose() {
        // Pins the documented discrepancy: the paper's sign gives Rᵀ for ϑ = φ(q).
        let q = UnitQuaternion::from_euler_angles(0.3, -0.2, 1.1).into_inner();
        let m = mrp_from_quaternion(&q).unwrap();
        let s = m.cross_matrix();
        let n2 = m.norm_squared();
        let printed = Matrix3::identity()
            + (s * s * 8.0 - s * (4.0 * (1.0 - n2))) / ((1.0 + n2) * (1.0 + n2));
        assert_relative_eq!(
            printed,
            rotation_from_quaternion(&q).transpose(),
            epsilon = 1e-12
        );
    }

    #[test]
    fn infinity_cases_are_reported() {
        assert!(mrp_from_quaternion(&Quaternion::new(-1.0, 0.0, 0.0, 0.0)).is_none());
        assert!(shadow_mrp(&Vector3::<f64>::zeros()).is_none());
    }
}
