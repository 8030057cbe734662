//! Closed real intervals with outward-rounded arithmetic.
//!
//! Every operation computes its endpoints in round-to-nearest `f64` and then moves the lower
//! endpoint one representable number down and the upper one up ([`next_down`], [`next_up`]).
//! IEEE 754 `+ − × ÷ √` are correctly rounded (error ≤ ½ ulp), so the result contains the exact
//! real result for every choice of operands in the operand intervals. Endpoint products `0·∞`
//! are taken as 0 (the usual convention of extended interval arithmetic); a divisor interval
//! containing 0 gives the whole line, never NaN.
//!
//! Own type rather than the `inari` crate: `inari` needs `-C target-cpu=haswell` (or newer) for
//! the whole workspace, which could change the code generated for the paper reproduction, whose
//! output must stay byte-identical.

use core::ops::{Add, Div, Mul, Neg, Sub};

/// The next representable `f64` above `x` (`+∞` stays; NaN stays NaN).
///
/// Own bit-level version because `f64::next_up` needs a newer Rust than the workspace's
/// `rust-version`.
#[inline]
pub fn next_up(x: f64) -> f64 {
    if x.is_nan() || x == f64::INFINITY {
        return x;
    }
    if x == 0.0 {
        return f64::from_bits(1);
    }
    let bits = x.to_bits();
    f64::from_bits(if x > 0.0 { bits + 1 } else { bits - 1 })
}

/// The next representable `f64` below `x` (`−∞` stays; NaN stays NaN).
#[inline]
pub fn next_down(x: f64) -> f64 {
    -next_up(-x)
}

/// A closed interval `[lo, hi]` of reals (`lo ≤ hi`; endpoints may be infinite).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    /// Lower endpoint.
    pub lo: f64,
    /// Upper endpoint.
    pub hi: f64,
}

/// `a·b` for endpoint products, with `0·∞ = 0`.
#[inline]
fn endpoint_product(a: f64, b: f64) -> f64 {
    let p = a * b;
    if p.is_nan() {
        0.0
    } else {
        p
    }
}

impl Interval {
    /// The whole real line: the result of an operation whose operands leave its domain.
    pub const ENTIRE: Interval = Interval {
        lo: f64::NEG_INFINITY,
        hi: f64::INFINITY,
    };

    /// `[lo, hi]`. A NaN or reversed pair gives [`Interval::ENTIRE`] (sound, never narrower).
    #[inline]
    pub fn new(lo: f64, hi: f64) -> Self {
        if lo <= hi {
            Self { lo, hi }
        } else {
            Self::ENTIRE
        }
    }

    /// The degenerate interval `[x, x]` (`x` is taken as the exact real it represents).
    #[inline]
    pub fn point(x: f64) -> Self {
        Self::new(x, x)
    }

    /// `[−r, r]` for `r ≥ 0`.
    #[inline]
    pub fn symmetric(r: f64) -> Self {
        Self::new(-r, r)
    }

    /// `lo`, `hi` moved outward by `|x|·2⁻⁵² + 2⁻¹⁰⁷⁴`, at least one ulp (an ulp of a normal
    /// `x` is at most `|x|·2⁻⁵²`; the smallest subnormal covers the rest), without the branches
    /// of [`next_down`]/[`next_up`]. The subtraction's own rounding cannot undo the step: the
    /// exact result is at or below the predecessor of `lo`, and rounding is monotone. A NaN
    /// (from an infinite endpoint on the wrong side) gives [`Interval::ENTIRE`].
    #[inline]
    fn widen(lo: f64, hi: f64) -> Self {
        const TINY: f64 = 5e-324;
        Self::new(
            lo - (lo.abs() * f64::EPSILON + TINY),
            hi + (hi.abs() * f64::EPSILON + TINY),
        )
    }

    /// The midpoint (rounded; it lies in the interval for finite endpoints).
    #[inline]
    pub fn mid(&self) -> f64 {
        0.5 * self.lo + 0.5 * self.hi
    }

    /// `hi − lo`, rounded up.
    #[inline]
    pub fn width(&self) -> f64 {
        next_up(self.hi - self.lo)
    }

    /// The magnitude `max(|lo|, |hi|)`: the largest absolute value in the interval.
    #[inline]
    pub fn mag(&self) -> f64 {
        self.lo.abs().max(self.hi.abs())
    }

    /// Whether `x` lies in the interval.
    #[inline]
    pub fn contains(&self, x: f64) -> bool {
        self.lo <= x && x <= self.hi
    }

    /// `{x² : x ∈ self}` (tighter than `self · self`, which ignores that both factors agree).
    #[inline]
    pub fn sqr(self) -> Self {
        let (a, b) = (self.lo.abs(), self.hi.abs());
        if self.lo <= 0.0 && self.hi >= 0.0 {
            Self::new(0.0, next_up(a.max(b) * a.max(b)))
        } else {
            let (m, n) = (a.min(b), a.max(b));
            Self::new(next_down(m * m).max(0.0), next_up(n * n))
        }
    }

    /// `{√x : x ∈ self, x ≥ 0}`; negative parts are cut off (callers take roots of quantities
    /// that are non-negative by construction, e.g. sums of squares).
    #[inline]
    pub fn sqrt(self) -> Self {
        let lo = if self.lo <= 0.0 {
            0.0
        } else {
            next_down(self.lo.sqrt()).max(0.0)
        };
        let hi = if self.hi < 0.0 {
            0.0
        } else {
            next_up(self.hi.sqrt())
        };
        Self::new(lo, hi)
    }

    /// `{|x| : x ∈ self}`.
    #[inline]
    pub fn abs(self) -> Self {
        if self.lo >= 0.0 {
            self
        } else if self.hi <= 0.0 {
            -self
        } else {
            Self::new(0.0, self.mag())
        }
    }

    /// `{max(x, y)}`-free hull: the smallest interval containing both.
    #[inline]
    pub fn hull(self, other: Self) -> Self {
        Self::new(self.lo.min(other.lo), self.hi.max(other.hi))
    }

    /// Cosine and sine on an interval inside `[0, π/2]`, where the cosine decreases and the
    /// sine increases (so the endpoints give the range). Two ulps outward cover the platform
    /// `libm`'s error (documented below one ulp for glibc and the Rust `std` targets in use).
    /// Outside that domain both are `[−1, 1]` (sound).
    pub fn cos_sin(self) -> (Self, Self) {
        let unit = Self::new(-1.0, 1.0);
        if !(self.lo >= 0.0 && self.hi <= core::f64::consts::FRAC_PI_2) {
            return (unit, unit);
        }
        let out = |lo: f64, hi: f64| {
            Self::new(
                next_down(next_down(lo)).max(-1.0),
                next_up(next_up(hi)).min(1.0),
            )
        };
        (
            out(self.hi.cos(), self.lo.cos()),
            out(self.lo.sin(), self.hi.sin()),
        )
    }
}

impl Add for Interval {
    type Output = Interval;
    #[inline]
    fn add(self, o: Interval) -> Interval {
        Interval::widen(self.lo + o.lo, self.hi + o.hi)
    }
}

impl Sub for Interval {
    type Output = Interval;
    #[inline]
    fn sub(self, o: Interval) -> Interval {
        Interval::widen(self.lo - o.hi, self.hi - o.lo)
    }
}

impl Neg for Interval {
    type Output = Interval;
    #[inline]
    fn neg(self) -> Interval {
        Interval {
            lo: -self.hi,
            hi: -self.lo,
        }
    }
}

impl Mul for Interval {
    type Output = Interval;
    #[inline]
    fn mul(self, o: Interval) -> Interval {
        let p = [
            self.lo * o.lo,
            self.lo * o.hi,
            self.hi * o.lo,
            self.hi * o.hi,
        ];
        // NaN only from 0·∞ (rare): then the endpoint convention 0·∞ = 0.
        let p = if p.iter().any(|x| x.is_nan()) {
            [
                endpoint_product(self.lo, o.lo),
                endpoint_product(self.lo, o.hi),
                endpoint_product(self.hi, o.lo),
                endpoint_product(self.hi, o.hi),
            ]
        } else {
            p
        };
        // Plain comparisons (no NaN left): cheaper than f64::min/max.
        let min = |a: f64, b: f64| if a < b { a } else { b };
        let max = |a: f64, b: f64| if a > b { a } else { b };
        Interval::widen(
            min(min(p[0], p[1]), min(p[2], p[3])),
            max(max(p[0], p[1]), max(p[2], p[3])),
        )
    }
}

impl Div for Interval {
    type Output = Interval;
    #[inline]
    fn div(self, o: Interval) -> Interval {
        if o.lo <= 0.0 && o.hi >= 0.0 {
            return Interval::ENTIRE;
        }
        let q = [
            self.lo / o.lo,
            self.lo / o.hi,
            self.hi / o.lo,
            self.hi / o.hi,
        ];
        if q.iter().any(|x| x.is_nan()) {
            return Interval::ENTIRE;
        }
        let lo = q[0].min(q[1]).min(q[2].min(q[3]));
        let hi = q[0].max(q[1]).max(q[2].max(q[3]));
        Interval::widen(lo, hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn next_up_and_down_step_one_ulp() {
        for x in [1.0, -1.0, 0.0, 1e-300, -3.5e10, f64::MAX] {
            let u = next_up(x);
            assert!(u > x);
            assert_eq!(next_down(u), x);
        }
        assert_eq!(next_up(1.0), 1.0 + f64::EPSILON);
        assert_eq!(next_up(f64::INFINITY), f64::INFINITY);
    }

    /// Products and quotients of sampled members stay inside the interval results.
    #[test]
    fn operations_contain_sampled_results() {
        let pts = |i: Interval| [i.lo, i.mid(), i.hi, 0.3 * i.lo + 0.7 * i.hi];
        let cases = [
            Interval::new(-1.3, 2.7),
            Interval::new(0.1, 0.2),
            Interval::new(-5.0, -0.25),
            Interval::new(1.0 / 3.0, 7.0 / 3.0),
        ];
        for a in cases {
            for b in cases {
                for x in pts(a) {
                    for y in pts(b) {
                        assert!((a + b).contains(x + y));
                        assert!((a - b).contains(x - y));
                        assert!((a * b).contains(x * y));
                        assert!((a / b).contains(x / y) || b.contains(0.0));
                        assert!(a.sqr().contains(x * x));
                        assert!(a.abs().contains(x.abs()));
                        if x >= 0.0 {
                            assert!(a.sqrt().contains(x.sqrt()));
                        }
                    }
                }
            }
        }
        let (c, s) = Interval::new(0.2, 0.7).cos_sin();
        assert!(c.contains(0.5f64.cos()) && s.contains(0.5f64.sin()));
        assert_eq!(
            Interval::new(1.0, 2.0) / Interval::new(-1.0, 1.0),
            Interval::ENTIRE
        );
    }
}
