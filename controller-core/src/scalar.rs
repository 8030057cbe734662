//! The scalar the law is generic over: `f32` on the MCU, `f64` on the host.

use nalgebra::{ComplexField, Dim, Matrix, Quaternion, RealField, Storage, UnitQuaternion};

/// A real scalar usable by the controller: `f32` or `f64`.
///
/// Transcendental functions come from `libm` through nalgebra's `libm` feature, so the
/// `no_std` build computes the same exact (correctly rounded to within 1 ulp) functions
/// as the host. Approximate maths (e.g. micromath) must not enter the control law.
pub trait Scalar: RealField + Copy {
    /// The correctly rounded (IEEE 754) square root.
    ///
    /// `f32` on an ARM hard-float target (the Cortex-M4F) uses the FPU's `vsqrt.f32` (see
    /// [`sqrt_f32`]; `libm`'s software `sqrtf` costs about 50 instructions); everywhere else, and for `f64`,
    /// it is `ComplexField::sqrt` (`libm` or `std`). IEEE 754 requires the square root to be
    /// correctly rounded, so both give the same bits for every input (NaN payloads aside).
    /// The control law uses this for every square root and norm on the step's path
    /// ([`norm`], [`normalize`], [`normalize_quaternion`]).
    fn sqrt_ieee(self) -> Self;

    /// `(sin self, cos self)` for the reference trajectory's sinusoids (not the law):
    /// `ComplexField::sin_cos` (correctly rounded), except for `f32` with the crate feature
    /// `sin-cos-f32`: [`crate::trig::sin_cos_f32`], within `2⁻²³` of the exact values in
    /// `f32` arithmetic only (`libm`'s `sincosf` runs in soft `f64` on the Cortex-M4F, about
    /// 1 900 instructions). The firmware's bare-metal build turns the feature on; host builds
    /// (the paper run in `f32`, SIL) keep the exact functions.
    fn sin_cos_bounded(self) -> (Self, Self);
}

impl Scalar for f32 {
    #[inline(always)]
    fn sqrt_ieee(self) -> Self {
        sqrt_f32(self)
    }

    #[inline(always)]
    fn sin_cos_bounded(self) -> (Self, Self) {
        #[cfg(feature = "sin-cos-f32")]
        {
            crate::trig::sin_cos_f32(self)
        }
        #[cfg(not(feature = "sin-cos-f32"))]
        {
            ComplexField::sin_cos(self)
        }
    }
}

impl Scalar for f64 {
    #[inline(always)]
    fn sqrt_ieee(self) -> Self {
        ComplexField::sqrt(self)
    }

    #[inline(always)]
    fn sin_cos_bounded(self) -> (Self, Self) {
        ComplexField::sin_cos(self)
    }
}

/// The correctly rounded square root of an `f32`: `vsqrt.f32` on ARM hard-float targets
/// (every `eabihf` ARM core has a VFP unit with single-precision `VSQRT`), `libm`/`std`
/// elsewhere. Bit-identical on both (IEEE 754 square root); a negative input gives NaN.
///
/// The value travels through a core register and the scratch `s15` (declared clobbered):
/// stable rustc (1.95) refuses `sreg` operands on `thumbv7em-none-eabihf`, whose FPU target
/// feature (`vfp4d16sp`, implying LLVM's `vfp2sp`) has no stable Rust name. So 5 instructions (4 `vmov` and the `vsqrt`) instead of 1, against
/// about 50 for `libm`'s software square root.
#[inline(always)]
pub fn sqrt_f32(x: f32) -> f32 {
    #[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
    {
        let bits: u32;
        // SAFETY: moves a word into s15 (declared clobbered), takes its square root on the FPU
        // and moves it back; no memory, no stack, no condition flags (only FPSCR's cumulative
        // exception bits change).
        unsafe {
            core::arch::asm!(
                "vmov s15, {x}",
                "vsqrt.f32 s15, s15",
                "vmov {r}, s15",
                x = in(reg) x.to_bits(),
                r = lateout(reg) bits,
                out("s15") _,
                options(pure, nomem, nostack, preserves_flags)
            );
        }
        f32::from_bits(bits)
    }
    #[cfg(not(all(target_arch = "arm", target_abi = "eabihf")))]
    {
        ComplexField::sqrt(x)
    }
}

/// `min(x, y)` of two `f32` with `fminf`'s semantics (IEEE 754-2008 `minNum`: `x` if `x < y`
/// or `y` is NaN, else `y`), inline. On the Cortex-M4F (no `vminnm`) `f32::min` is a call to
/// `compiler_builtins`' `fminf`, about 12 instructions; this is about 4, with the same bits
/// for every non-NaN result (and the same choice between `±0` as `fminf`).
#[inline(always)]
pub fn fmin(x: f32, y: f32) -> f32 {
    if y.is_nan() || x < y {
        x
    } else {
        y
    }
}

/// `max(x, y)` with `fmaxf`'s semantics (IEEE 754-2008 `maxNum`: `y` if `x < y` or `x` is
/// NaN, else `x`), inline; see [`fmin`].
#[inline(always)]
pub fn fmax(x: f32, y: f32) -> f32 {
    if x.is_nan() || x < y {
        y
    } else {
        x
    }
}

/// Adds `0 · x` for every entry `x` of `m` to `probe`. Starting from zero, the probe stays `±0`
/// while every value added is finite and becomes NaN at the first infinite or NaN one
/// (`0 · ∞` and `0 · NaN` are NaN, and NaN propagates through the sum), so `probe.is_finite()`
/// answers "all finite" for many values at once: one multiply-add per value on the
/// Cortex-M4F (`vmla.f32`) instead of a move, mask, compare and branch per value.
#[inline(always)]
pub fn finite_probe<T: Scalar, R: Dim, C: Dim, S: Storage<T, R, C>>(
    probe: T,
    m: &Matrix<T, R, C, S>,
) -> T {
    m.iter().fold(probe, |p, &x| p + x * T::zero())
}

/// Euclidean norm of a vector (Frobenius norm of a matrix) with [`Scalar::sqrt_ieee`]: the same
/// bits as nalgebra's `norm()` (which is `norm_squared().sqrt()`), without `libm`'s software
/// square root on the MCU.
#[inline(always)]
pub fn norm<T: Scalar, R: Dim, C: Dim, S: Storage<T, R, C>>(m: &Matrix<T, R, C, S>) -> T {
    m.norm_squared().sqrt_ieee()
}

/// `v / |v|` as nalgebra's `normalize()` computes it (each component divided by [`norm`]).
#[inline(always)]
pub fn normalize<T: Scalar, R: Dim, C: Dim, S: Storage<T, R, C>>(
    m: &Matrix<T, R, C, S>,
) -> nalgebra::OMatrix<T, R, C>
where
    nalgebra::DefaultAllocator: nalgebra::allocator::Allocator<R, C>,
{
    m.unscale(norm(m))
}

/// The unit quaternion `q / |q|` exactly as `UnitQuaternion::from_quaternion` computes it
/// (each component divided by the norm), with [`Scalar::sqrt_ieee`].
#[inline(always)]
pub fn normalize_quaternion<T: Scalar>(q: Quaternion<T>) -> UnitQuaternion<T> {
    UnitQuaternion::new_unchecked(Quaternion::from(q.coords.unscale(norm(&q.coords))))
}

/// Converts an `f64` literal to the scalar `T` (rounding to nearest for `f32`).
#[inline(always)]
pub fn lit<T: Scalar>(x: f64) -> T {
    nalgebra::convert(x)
}

/// Converts a scalar back to `f64`, for diagnostics and comparisons.
#[inline(always)]
pub fn to_f64<T: Scalar>(x: T) -> f64 {
    nalgebra::try_convert(x).unwrap_or(f64::NAN)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Vector3, Vector4};

    /// `finite_probe` is finite exactly when every value is, for every position of one
    /// special value (±∞, NaN) among large, tiny and zero finite ones, in f32 and f64.
    #[test]
    fn finite_probe_flags_any_non_finite_value() {
        let finite = [3.0e38f32, -3.0e38, 1e-45, -0.0, 0.0, 1.0, -7.5];
        for special in [f32::INFINITY, f32::NEG_INFINITY, f32::NAN] {
            for at in 0..=finite.len() {
                let mut v = [0.0f32; 8];
                let (before, after) = finite.split_at(at);
                v[..at].copy_from_slice(before);
                v[at] = special;
                v[at + 1..].copy_from_slice(after);
                let m = nalgebra::SVector::<f32, 8>::from(v);
                assert!(!finite_probe(0.0, &m).is_finite(), "{v:?}");
                assert!(!finite_probe(0.0, &m.map(f64::from)).is_finite(), "{v:?}");
            }
        }
        let m = nalgebra::SVector::<f32, 7>::from(finite);
        assert_eq!(finite_probe(0.0f32, &m), 0.0);
        assert!(finite_probe(0.0, &m.map(f64::from)).is_finite());
    }

    /// The helpers give the same bits as nalgebra's own norm / normalize / from_quaternion,
    /// and `sqrt_f32` equals the correctly rounded square root on a sweep of inputs
    /// (including subnormals, zeros, powers of two and values next to them).
    #[test]
    fn same_bits_as_nalgebra() {
        let mut x = 0x2545_f491u32;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            f32::from_bits(x & 0x7fff_ffff)
        };
        for _ in 0..200_000 {
            let a = next();
            if a.is_finite() {
                assert_eq!(sqrt_f32(a).to_bits(), a.sqrt().to_bits(), "{a:e}");
                assert_eq!(
                    sqrt_f32(a).to_bits(),
                    ((a as f64).sqrt() as f32).to_bits(),
                    "{a:e}"
                );
            }
        }
        for a in [
            0.0f32,
            -0.0,
            f32::MIN_POSITIVE,
            1e-45,
            1.0,
            2.0,
            4.0,
            f32::MAX,
        ] {
            assert_eq!(sqrt_f32(a).to_bits(), a.sqrt().to_bits());
        }
        assert!(sqrt_f32(-1.0).is_nan());
        // fmin/fmax: libm's fminf/fmaxf, bit for bit (signed zeros included).
        let cases = [
            0.0f32,
            -0.0,
            1.0,
            -1.0,
            0.5,
            f32::INFINITY,
            f32::NEG_INFINITY,
            1e-45,
        ];
        for &a in &cases {
            for &b in &cases {
                assert_eq!(fmin(a, b).to_bits(), libm::fminf(a, b).to_bits(), "{a} {b}");
                assert_eq!(fmax(a, b).to_bits(), libm::fmaxf(a, b).to_bits(), "{a} {b}");
            }
            assert_eq!(fmin(a, f32::NAN), a);
            assert_eq!(fmin(f32::NAN, a), a);
            assert_eq!(fmax(a, f32::NAN), a);
            assert_eq!(fmax(f32::NAN, a), a);
        }
        let mut s = 0.37f32;
        for _ in 0..1000 {
            s = (s * 7.31).fract() - 0.5;
            let v = Vector3::new(s, 0.3 - s * s, 2.0 * s + 0.1) * 3.7;
            assert_eq!(norm(&v).to_bits(), v.norm().to_bits());
            assert_eq!(normalize(&v), v.normalize());
            let q = Quaternion::from(Vector4::new(s, 1.0 - s, 0.2, -0.7 * s));
            assert_eq!(normalize_quaternion(q), UnitQuaternion::from_quaternion(q));
            let d = Vector3::new(s as f64, 0.1, -2.0);
            assert_eq!(norm(&d).to_bits(), d.norm().to_bits());
        }
    }
}
