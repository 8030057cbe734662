//! Forward-mode differentiation over intervals: enclosures of a function and its gradient.
//!
//! A [`Gradient`] carries an interval enclosing `f(x)` and, per variable `j`, an interval
//! enclosing `∂f/∂x_j(x)`, both over every `x` of the box the variables were seeded with
//! ([`Gradient::variable`]). The chain rule is applied with interval arithmetic, so each
//! enclosure is rigorous (outward rounding is in [`Interval`]). The search uses them for the
//! mean-value form `f(X) ⊆ f(c) + Σ_j ∂_j f(X) (X_j − c_j)` (second-order tight in the box
//! width) and for the monotonicity test (a partial whose enclosure excludes 0).

use core::ops::{Add, Div, Mul, Neg, Sub};

use super::arith::Arith;
use super::interval::Interval;

/// Enclosures of a function value and of its partial derivatives with respect to `N ≤ 16`
/// variables over a box.
#[derive(Clone, Copy, Debug)]
pub struct Gradient<const N: usize> {
    /// Encloses `f` over the box.
    pub value: Interval,
    /// `partial[j]` encloses `∂f/∂x_j` over the box (exactly 0 where `active` has no bit `j`).
    pub partial: [Interval; N],
    /// Bit `j` set when `partial[j]` may be non-zero; the others are skipped (a variable fixed
    /// at a point, or a constant, has no active bit).
    active: u16,
}

const ZERO: Interval = Interval { lo: 0.0, hi: 0.0 };

impl<const N: usize> Gradient<N> {
    /// The variable `x_j` ranging over `range`: value `range`, gradient `e_j` (no partial at
    /// all when `range` is a point: the variable is then a constant of the box).
    pub fn variable(range: Interval, j: usize) -> Self {
        let mut partial = [ZERO; N];
        if range.lo == range.hi {
            return Self::fixed(range);
        }
        partial[j] = Interval::point(1.0);
        Self {
            value: range,
            partial,
            active: 1 << j,
        }
    }

    /// A quantity that does not depend on the variables.
    pub fn fixed(value: Interval) -> Self {
        Self {
            value,
            partial: [ZERO; N],
            active: 0,
        }
    }

    /// `f ∘ self` for a scalar function with value `f` and derivative `df` enclosed over
    /// `self.value`.
    #[inline]
    fn chain(self, f: Interval, df: Interval) -> Self {
        let mut partial = self.partial;
        for (j, p) in partial.iter_mut().enumerate() {
            if self.active >> j & 1 == 1 {
                *p = *p * df;
            }
        }
        Self {
            value: f,
            partial,
            active: self.active,
        }
    }

    /// `(cos x, sin x)` for `x ⊆ [0, π/2]` (see [`Interval::cos_sin`]).
    pub fn cos_sin(self) -> (Self, Self) {
        let (c, s) = self.value.cos_sin();
        (self.chain(c, -s), self.chain(s, c))
    }

    /// Combines the partials of `self` (`p`) and `o` (`q`) per active variable: `both(p, q)`
    /// where both are active, `left(p)` or `right(q)` where only one is.
    #[inline]
    fn combine(
        &self,
        o: &Self,
        value: Interval,
        both: impl Fn(Interval, Interval) -> Interval,
        left: impl Fn(Interval) -> Interval,
        right: impl Fn(Interval) -> Interval,
    ) -> Self {
        let active = self.active | o.active;
        let mut partial = [ZERO; N];
        for (j, r) in partial.iter_mut().enumerate() {
            *r = match (self.active >> j & 1, o.active >> j & 1) {
                (1, 1) => both(self.partial[j], o.partial[j]),
                (1, _) => left(self.partial[j]),
                (_, 1) => right(o.partial[j]),
                _ => continue,
            };
        }
        Self {
            value,
            partial,
            active,
        }
    }
}

impl<const N: usize> Add for Gradient<N> {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        self.combine(&o, self.value + o.value, |p, q| p + q, |p| p, |q| q)
    }
}

impl<const N: usize> Sub for Gradient<N> {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        self.combine(&o, self.value - o.value, |p, q| p - q, |p| p, |q| -q)
    }
}

impl<const N: usize> Neg for Gradient<N> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        Self {
            value: -self.value,
            partial: self.partial.map(|p| -p),
            active: self.active,
        }
    }
}

impl<const N: usize> Mul for Gradient<N> {
    type Output = Self;
    // The product rule needs `+` inside `mul`.
    #[allow(clippy::suspicious_arithmetic_impl)]
    #[inline]
    fn mul(self, o: Self) -> Self {
        let (a, b) = (self.value, o.value);
        self.combine(&o, a * b, |p, q| p * b + a * q, |p| p * b, |q| a * q)
    }
}

impl<const N: usize> Div for Gradient<N> {
    type Output = Self;
    // The quotient rule needs `−` and `×` inside `div`.
    #[allow(clippy::suspicious_arithmetic_impl)]
    #[inline]
    fn div(self, o: Self) -> Self {
        // (a/b)' = (a' − (a/b) b') / b: one division per partial.
        let b = o.value;
        let v = self.value / b;
        // One interval division; the partials multiply by the reciprocal.
        let r = Interval::point(1.0) / b;
        self.combine(&o, v, |p, q| (p - v * q) * r, |p| p * r, |q| -(v * q) * r)
    }
}

impl<const N: usize> Arith for Gradient<N> {
    #[inline]
    fn constant(c: f64) -> Self {
        Self::fixed(Interval::point(c))
    }
    #[inline]
    fn sqr(self) -> Self {
        let two_x = Interval::point(2.0) * self.value;
        self.chain(self.value.sqr(), two_x)
    }
    #[inline]
    fn sqrt(self) -> Self {
        let root = self.value.sqrt();
        // d√x/dx = 1/(2√x); unbounded when the box reaches x = 0.
        let d = Interval::point(0.5) / root;
        self.chain(root, d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// f(x, y) = x²y/(1 + √(x² + y²)) on a box: the enclosures contain the value and a
    /// central-difference derivative at interior points.
    #[test]
    fn encloses_value_and_partials() {
        let f = |x: f64, y: f64| x * x * y / (1.0 + (x * x + y * y).sqrt());
        let bx = Interval::new(0.5, 0.9);
        let by = Interval::new(-1.2, -0.3);
        let x = Gradient::<2>::variable(bx, 0);
        let y = Gradient::<2>::variable(by, 1);
        let one = Gradient::<2>::constant(1.0);
        let g = x.sqr() * y / (one + (x.sqr() + y.sqr()).sqrt());
        for a in [0.55, 0.7, 0.85] {
            for b in [-1.1, -0.7, -0.35] {
                let h = 1e-6;
                assert!(g.value.contains(f(a, b)));
                let dx = (f(a + h, b) - f(a - h, b)) / (2.0 * h);
                let dy = (f(a, b + h) - f(a, b - h)) / (2.0 * h);
                assert!(g.partial[0].contains(dx), "{:?} {dx}", g.partial[0]);
                assert!(g.partial[1].contains(dy), "{:?} {dy}", g.partial[1]);
            }
        }
    }
}
