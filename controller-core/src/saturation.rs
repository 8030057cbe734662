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
    x * (level / (level * level + x.norm_squared()).sqrt())
}
