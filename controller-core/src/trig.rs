//! Sine and cosine of an `f32` in `f32` arithmetic, with a stated error bound.
//!
//! `libm`'s `sincosf` evaluates its polynomials in `f64` for a correctly rounded result; on the
//! Cortex-M4F (single-precision FPU only) that is soft `f64`, about 1 900 instructions per call.
//! [`sin_cos_f32`] reduces the argument by `π/2` with a three-part Cody–Waite constant and
//! evaluates the Cephes minimax polynomials (S. L. Moshier, *Cephes Math Library*, `sinf.c`)
//! in `f32`: about 60 instructions, the same bits on every IEEE-754 target (no fused
//! multiply-add: Rust does not contract `a * b + c`).
//!
//! **Error bound** (checked by the tests below against `f64` `sin`/`cos` of the same `f32`
//! input, over every `f32` in `[0, 2π]` with a stride and random inputs up to
//! [`SIN_COS_REDUCED_MAX`]): for `|x| ≤` [`SIN_COS_REDUCED_MAX`], each of `sin x`, `cos x` is
//! within [`SIN_COS_ABS_ERROR`] (`2⁻²³ ≈ 1.19e-7`, one ulp of 1; the largest error seen is
//! 9.3e-8) of the exact value. Beyond
//! that (and for non-finite inputs) it returns `libm`'s correctly rounded result.
//! With the crate feature `sin-cos-f32` (the firmware's bare-metal build), the controller uses it
//! for the reference trajectory's sinusoids
//! ([`crate::Scalar::sin_cos_bounded`]); the law itself keeps exact functions.

use nalgebra::ComplexField;

/// Largest `|x|` \[rad\] reduced here; larger arguments go to `libm`.
pub const SIN_COS_REDUCED_MAX: f32 = 8192.0;

/// Bound on `|sin_cos_f32(x).k − (sin x, cos x).k|` for `|x| ≤` [`SIN_COS_REDUCED_MAX`]:
/// `2⁻²³`.
pub const SIN_COS_ABS_ERROR: f32 = 1.0 / 8_388_608.0;

/// `2/π`.
const TWO_OVER_PI: f32 = 0.636_619_75;
/// `π/2` in three parts (Cody–Waite): `C1` and `C2` have 11 significant bits, so `q · C1` and
/// `q · C2` are exact for the quadrant counts `q < 2¹³` of `|x| ≤` [`SIN_COS_REDUCED_MAX`];
/// `C1 + C2 + C3` is `π/2` within 2e-15 (the shortest decimal forms of the `f32` values).
const C1: f32 = 1.570_312_5;
const C2: f32 = 4.837_513e-4;
const C3: f32 = 7.549_79e-8;

/// `sin r` for `|r| ≤ π/4` (Cephes `sinf` polynomial).
#[inline(always)]
fn sin_poly(r: f32, z: f32) -> f32 {
    r + r * z * ((-1.951_529_6e-4 * z + 8.332_161e-3) * z - 1.666_665_5e-1)
}

/// `cos r` for `|r| ≤ π/4` (Cephes `cosf` polynomial), `z = r²`.
#[inline(always)]
fn cos_poly(z: f32) -> f32 {
    1.0 - 0.5 * z + z * z * ((2.443_315_7e-5 * z - 1.388_731_6e-3) * z + 4.166_664_6e-2)
}

/// `(sin x, cos x)` of `x` \[rad\], each within [`SIN_COS_ABS_ERROR`] of the exact value for
/// `|x| ≤` [`SIN_COS_REDUCED_MAX`] (see the module docs); `libm`'s `sincosf` beyond, and for
/// NaN or infinite `x` (NaN results).
#[inline]
pub fn sin_cos_f32(x: f32) -> (f32, f32) {
    let a = x.abs();
    // NaN and ±∞ go to libm too.
    if a.is_nan() || a > SIN_COS_REDUCED_MAX {
        return ComplexField::sin_cos(x);
    }
    // The nearest quadrant point q π/2: r = a − q π/2 is in [−π/4, π/4] (to rounding).
    let q = (a * TWO_OVER_PI + 0.5) as u32;
    let y = q as f32;
    let r = ((a - y * C1) - y * C2) - y * C3;
    let z = r * r;
    let (s, c) = (sin_poly(r, z), cos_poly(z));
    let (sin_a, cos_a) = match q & 3 {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    };
    (if x.is_sign_negative() { -sin_a } else { sin_a }, cos_a)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The largest error of `sin_cos_f32` against the `f64` functions over `xs`, and where.
    fn worst(xs: impl Iterator<Item = f32>) -> (f64, f32) {
        let mut w = (0.0f64, 0.0f32);
        for x in xs {
            let (s, c) = sin_cos_f32(x);
            let e = (f64::from(s) - f64::from(x).sin())
                .abs()
                .max((f64::from(c) - f64::from(x).cos()).abs());
            if e > w.0 {
                w = (e, x);
            }
        }
        w
    }

    /// Every 61st `f32` in `[0, 2π]` and its negation: 3.6e7 inputs, all quadrants.
    #[test]
    fn bound_holds_on_one_period() {
        let hi = (2.0 * core::f32::consts::PI).to_bits();
        let (e, x) = worst((0..=hi).step_by(61).flat_map(|b| {
            let x = f32::from_bits(b);
            [x, -x]
        }));
        assert!(e <= f64::from(SIN_COS_ABS_ERROR), "error {e:e} at {x}");
    }

    /// Random inputs over the whole reduced range (a fixed-seed xorshift, so reproducible).
    #[test]
    fn bound_holds_up_to_the_reduction_limit() {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let xs = core::iter::repeat_with(move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            ((state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0) as f32 * SIN_COS_REDUCED_MAX
        });
        let (e, x) = worst(xs.take(4_000_000));
        assert!(e <= f64::from(SIN_COS_ABS_ERROR), "error {e:e} at {x}");
        let (e, x) = worst((0..=1_000_000).map(|k| SIN_COS_REDUCED_MAX - k as f32 * 1e-3));
        assert!(e <= f64::from(SIN_COS_ABS_ERROR), "error {e:e} at {x}");
    }

    /// Exact at the quadrant points' neighbours, odd/even symmetry, and libm's values beyond
    /// the reduced range and for non-finite inputs.
    #[test]
    fn symmetry_and_fallback() {
        for x in [0.0f32, 1e-30, 0.5, 1.0, 3.0, 100.0, 8000.0] {
            let (s, c) = sin_cos_f32(x);
            let (sn, cn) = sin_cos_f32(-x);
            assert_eq!((sn.to_bits(), cn.to_bits()), ((-s).to_bits(), c.to_bits()));
        }
        assert_eq!(sin_cos_f32(0.0), (0.0, 1.0));
        assert_eq!(sin_cos_f32(1e-30).0, 1e-30);
        for x in [8192.5f32, -1e6, 3.0e38] {
            let (s, c) = sin_cos_f32(x);
            assert_eq!((s, c), (libm::sinf(x), libm::cosf(x)), "{x}");
        }
        let (s, c) = sin_cos_f32(f32::NAN);
        assert!(s.is_nan() && c.is_nan());
        let (s, c) = sin_cos_f32(f32::INFINITY);
        assert!(s.is_nan() && c.is_nan());
    }
}
