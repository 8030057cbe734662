//! The arithmetic the desired-rate formulas need, over points, intervals and gradients.
//!
//! One generic implementation of the formulas ([`super::desired_rates`]) serves three number
//! types: `f64` (point values, compared with `controller_core::desired_attitude` in the tests
//! and used for the search's lower bounds), [`Interval`] (rigorous enclosures) and
//! [`super::gradient::Gradient`] (enclosures of the value and of its partial derivatives).

use core::ops::{Add, Div, Mul, Neg, Sub};

use super::interval::Interval;

/// A number type closed under the field operations, squares and square roots.
pub trait Arith:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// The constant `c` (taken as the exact real the `f64` represents).
    fn constant(c: f64) -> Self;
    /// `x²` (for intervals: tighter than `x·x`).
    fn sqr(self) -> Self;
    /// `√x` for `x ≥ 0`.
    fn sqrt(self) -> Self;
}

impl Arith for f64 {
    #[inline]
    fn constant(c: f64) -> Self {
        c
    }
    #[inline]
    fn sqr(self) -> Self {
        self * self
    }
    #[inline]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
}

impl Arith for Interval {
    #[inline]
    fn constant(c: f64) -> Self {
        Interval::point(c)
    }
    #[inline]
    fn sqr(self) -> Self {
        Interval::sqr(self)
    }
    #[inline]
    fn sqrt(self) -> Self {
        Interval::sqrt(self)
    }
}

/// A 3-vector of any [`Arith`] type (inertial or body frame as the caller says).
pub type V3<T> = [T; 3];

/// `a·b`.
#[inline]
pub fn dot<T: Arith>(a: &V3<T>, b: &V3<T>) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `a × b`.
#[inline]
pub fn cross<T: Arith>(a: &V3<T>, b: &V3<T>) -> V3<T> {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `|a|²`, with [`Arith::sqr`] per component.
#[inline]
pub fn norm_squared<T: Arith>(a: &V3<T>) -> T {
    a[0].sqr() + a[1].sqr() + a[2].sqr()
}

/// `a s`.
#[inline]
pub fn scale<T: Arith>(a: &V3<T>, s: T) -> V3<T> {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// `a + b`.
#[inline]
pub fn add<T: Arith>(a: &V3<T>, b: &V3<T>) -> V3<T> {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// `a − b`.
#[inline]
pub fn sub<T: Arith>(a: &V3<T>, b: &V3<T>) -> V3<T> {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
