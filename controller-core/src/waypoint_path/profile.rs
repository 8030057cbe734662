//! The rest-to-rest profile of one leg: `φ(s) = 126s⁵ − 420s⁶ + 540s⁷ − 315s⁸ + 70s⁹` on
//! `s ∈ [0, 1]`, the degree-9 polynomial with `φ(0) = 0`, `φ(1) = 1` and its first four
//! derivatives zero at both ends. A leg `p(t) = a + (b − a) φ(t/T)` therefore starts and stops
//! at rest with zero acceleration, jerk and snap, so legs and holds join into a reference that
//! is four times continuously differentiable, as Assumption 1 needs (`p_d⁽⁴⁾` enters the
//! feedforward `ω̇_d`, eq:DesiredAngularVelocity).

use crate::scalar::{lit, Scalar};

/// `sup_{s∈[0,1]} |φ⁽ᵏ⁾(s)|` for k = 1..4, rounded up. `φ'` peaks at `s = 1/2` at exactly
/// 315/128 = 2.4609375 and `φ'''` there at exactly 315/4 = 78.75; `φ''` and `φ''''` peak at
/// irrational points (about 9.371976 and 622.53274). The tests recompute all four by dense
/// sampling with a curvature margin and check each entry is an upper bound within 1e-6
/// relative.
pub const PEAK: [f64; 4] = [2.460_938, 9.371_977, 78.750_01, 622.532_8];

/// `(φ, φ', φ'', φ''', φ'''')` at `s`, clamped to `[0, 1]` (before: at rest at 0; after: at
/// rest at 1).
pub fn eval<T: Scalar>(s: T) -> [T; 5] {
    if s <= T::zero() {
        return [T::zero(); 5];
    }
    if s >= T::one() {
        return [T::one(), T::zero(), T::zero(), T::zero(), T::zero()];
    }
    // Horner in s of each derivative's coefficients (powers below the first non-zero one
    // factored out: φ⁽ᵏ⁾ has a zero of order 5 − k at s = 0).
    let horner = |c: &[f64]| c.iter().rev().fold(T::zero(), |acc, &a| acc * s + lit(a));
    let s2 = s * s;
    let s3 = s2 * s;
    let s4 = s3 * s;
    let s5 = s4 * s;
    [
        s5 * horner(&[126.0, -420.0, 540.0, -315.0, 70.0]),
        s4 * horner(&[630.0, -2520.0, 3780.0, -2520.0, 630.0]),
        s3 * horner(&[2520.0, -12600.0, 22680.0, -17640.0, 5040.0]),
        s2 * horner(&[7560.0, -50400.0, 113400.0, -105840.0, 35280.0]),
        s * horner(&[15120.0, -151200.0, 453600.0, -529200.0, 211680.0]),
    ]
}
