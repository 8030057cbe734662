//! One inequality of a certificate with both sides ([`Condition`]), the refusal it becomes when
//! it fails ([`Violation`]), and the strict comparison every refusal uses.
//!
//! Shared by the paper's certificate ([`crate::certify`]: Assumption 1, Theorems 1-2, Lemma 1)
//! and the integral action's local stability conditions ([`crate::integral_stability`]).

use crate::scalar::Scalar;

/// One inequality of the paper, with both sides.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Condition<T: Scalar> {
    /// Stable identifier, e.g. `"theorem2.torque_max_yaw"`.
    pub name: &'static str,
    /// The inequality as written, with the paper's label.
    pub statement: &'static str,
    /// Left-hand side (the larger side when the condition holds).
    pub lhs: T,
    /// Right-hand side.
    pub rhs: T,
    /// Whether `lhs > rhs` (or `lhs ≥ rhs` for non-strict conditions) holds.
    pub holds: bool,
}

impl<T: Scalar> Condition<T> {
    /// The strict inequality `lhs > rhs` named `name`, stated as `statement`.
    pub fn strict(name: &'static str, statement: &'static str, lhs: T, rhs: T) -> Self {
        Self {
            name,
            statement,
            lhs,
            rhs,
            holds: lhs > rhs,
        }
    }
}

/// A violated condition: its name, statement and numbers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Violation {
    /// Identifier of the condition.
    pub name: &'static str,
    /// The inequality as written.
    pub statement: &'static str,
    /// Left-hand side value.
    pub lhs: f64,
    /// Right-hand side value.
    pub rhs: f64,
}

impl core::fmt::Display for Violation {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(
            f,
            "infeasible: {} violated ({}): lhs = {:.6}, rhs = {:.6}",
            self.name, self.statement, self.lhs, self.rhs
        )
    }
}

/// `a < b`, false when either is NaN (so refusals catch NaN too).
pub(crate) fn strictly_less<T: Scalar>(a: T, b: T) -> bool {
    a.partial_cmp(&b) == Some(core::cmp::Ordering::Less)
}
