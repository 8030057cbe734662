//! The scalar the law is generic over: `f32` on the MCU, `f64` on the host.

use nalgebra::RealField;

/// A real scalar usable by the controller: `f32` or `f64`.
///
/// Transcendental functions come from `libm` through nalgebra's `libm` feature, so the
/// `no_std` build computes the same exact (correctly rounded to within 1 ulp) functions
/// as the host. Approximate maths (e.g. micromath) must not enter the control law.
pub trait Scalar: RealField + Copy {}

impl<T: RealField + Copy> Scalar for T {}

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
