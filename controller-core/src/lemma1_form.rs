//! Which chain of inequalities bounds `|ω̇_d|`: the paper's Lemma 1, the same chain keeping
//! only the parts of `ρ̈` and `ϋ` that eq:DesiredAngularAcceleration uses (an extension;
//! docs/tangential-lemma1.md), or that chain per component of the desired frame for Theorem 2's
//! per-axis conditions (an extension; docs/torque-set.md).
//!
//! The law is the same every way; only the certificate's `U_ω̇d` (and `U*_ω̇d` of Assumption 1)
//! differ. All are proven bounds; the tangential one is never larger than the paper's, and the
//! desired frame's never larger than the tangential one.
//!
//! **The argument.** With `r = |u̇|/|u|`, `a = ρᵀu̇/|u|` and `b = |ρ̇|`, so `a² + b² = r²`,
//! the paper's expression `ρ̈ = P_ρ ü/|u| − 2a ρ̇ − b² ρ` (`P_ρ = I − ρρᵀ`) splits into a part
//! orthogonal to `ρ`, `P_ρ ü/|u| − 2a ρ̇`, and the radial `−b² ρ`.
//! - eq:DesiredAngularAcceleration reads `ρ̈` only through `υᵀ[ρ]×ρ̈` and `υᵀρ̈`, its
//!   components along the orthonormal pair `ρ × υ`, `υ` that spans the plane orthogonal to `ρ`;
//!   so only `|P_ρ ρ̈| ≤ |ü|/|u| + 2|a|b ≤ |ü|/|u| + r²` enters (the paper charges `3r²`).
//! - Its third component `−υᵀ[ρ]×ϋ = (ρ × υ)ᵀϋ` reads `ϋ` along a unit vector orthogonal to
//!   `υ`; with `ϋ = P_υ ϖ̈/|ϖ| − 2a' υ̇ − |υ̇|² υ` the same step gives
//!   `|P_υ ϋ| ≤ |P_υ ϖ̈|/|ϖ| + |ϖ̇|²/|ϖ|²`.
//! - `ϖ = M(ν_d) ρ` (for `ρ₃ > 0`) is linear in `ρ` and in `ν_d`, through matrices of norm
//!   `|ν_d|` and 1. In `ϖ̈ = M(ν_d) ρ̈ + 2M(ν̇_d) ρ̇ + M(ν̈_d) ρ`, the radial part of `ρ̈` gives a
//!   multiple of `M(ν_d) ρ = ϖ`, parallel to `υ`, which `P_υ` removes; so
//!   `|P_υ ϖ̈| ≤ |P_ρ ρ̈| + 2|ρ̇||ν̇_d| + |ν̈_d|` and `U_ϋ,⊥ = (U_ρ̈,⊥ + 2U_ρ̇ K_ν̇ + K_ν̈)/L_ϖ + U_υ̇²`
//!   (the paper: `(U_ρ̈ + …)/L_ϖ + 3U_υ̇²`).
//! - For the record, the whole `|ρ̈|` (no longer used by the chain) is at most
//!   `|ü|/|u| + (2/√3) r²`: `|ρ̈|² ≤ (|ü|/|u| + 2|a|b)² + b⁴`, `2|a|b ≤ r²` and
//!   `4a²b² + b⁴ = b²(4r² − 3b²) ≤ 4r⁴/3` (attained at `b² = 2r²/3`).
//!
//! Everything else is the paper's Lemma 1 step for step, so every bound of [`crate::certify`]
//! that uses `U_ω̇d` (Theorem 2, the torque set, Assumption 1's `U*`) stays a proven bound.

use crate::scalar::{lit, Scalar};

/// The chain [`crate::certify`] bounds `|ω̇_d|` with (Lemma 1); the law is the same for both.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Lemma1Form {
    /// The paper's Lemma 1: `U_ρ̈ = m U_ü/T_min + 3U_ρ̇²`, `U_ϋ = U_ϖ̈/L_ϖ + 3U_υ̇²`, bit for bit.
    #[default]
    Paper,
    /// Only the components eq:DesiredAngularAcceleration uses (extension,
    /// docs/tangential-lemma1.md): `U_ρ̈,⊥ = m U_ü/T_min + U_ρ̇²` bounds `|P_ρ ρ̈|`, and
    /// `U_ϋ,⊥ = (U_ρ̈,⊥ + 2U_ρ̇K_ν̇ + K_ν̈)/L_ϖ + U_υ̇²` bounds `|P_υ ϋ|`; both enter `U_ω̇d`.
    Tangential,
    /// The tangential chain, and Theorem 2's per-axis conditions (eq:TorqueMaxConditionsTheorem)
    /// judged with the norms of `ω_d`, `ω̇_d` that the desired frame's components give where they
    /// are tighter than the chain's (`crate::DesiredFrameBounds::norm_bounds`, the norms the
    /// certified torque set already takes): each condition is then the set's extent along its
    /// axis (extension, docs/torque-set.md#the-norms-the-set-takes).
    DesiredFrame,
}

/// The quadratic coefficients of one form's chain (dimensionless).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadraticCoefficients<T: Scalar> {
    /// `c` in `|ρ̈| ≤ |ü|/|u| + c (|u̇|/|u|)²`, the bound on all of `ρ̈` (reported as
    /// `Bounds::thrust_direction_acceleration`): 3 (paper), `2/√3` (tangential).
    pub whole: T,
    /// `c` in the bound on the part of `ρ̈` (resp. `ϋ`) that eq:DesiredAngularAcceleration reads,
    /// the one the chain uses: 3 (paper), 1 (tangential).
    pub projected: T,
}

impl Lemma1Form {
    /// This form's quadratic coefficients (module documentation for the argument).
    /// Source: Lemma 1's proof (paper); docs/tangential-lemma1.md (tangential).
    pub fn coefficients<T: Scalar>(self) -> QuadraticCoefficients<T> {
        match self {
            Self::Paper => QuadraticCoefficients {
                whole: lit(3.0),
                projected: lit(3.0),
            },
            Self::Tangential | Self::DesiredFrame => QuadraticCoefficients {
                whole: lit::<T>(2.0) / lit::<T>(3.0).sqrt(),
                projected: T::one(),
            },
        }
    }

    /// The name used in flight files, scenario files and reports: `"paper"`, `"tangential"` or
    /// `"desired_frame"`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Paper => "paper",
            Self::Tangential => "tangential",
            Self::DesiredFrame => "desired_frame",
        }
    }

    /// Whether Theorem 2's per-axis conditions take the desired frame's norms
    /// ([`Self::DesiredFrame`]) rather than the chain's.
    pub fn per_axis_from_desired_frame(self) -> bool {
        self == Self::DesiredFrame
    }
}

#[cfg(test)]
mod tests;
