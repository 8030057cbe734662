//! Bisection of a monotone predicate: the one loop behind the design's searches (`M_p,max`,
//! the largest certifiable reference scale, the largest converging motor time constant, the
//! lowest certified thrust floor).

use core::ops::{Add, Mul};

/// Halves the bracket between `pass` (where `holds` is true) and `fail` (where it is false)
/// `steps` times, keeping `holds` true at one end, and returns that end: the last point found
/// where it holds. `holds` must be monotone over the bracket (true on one side of a threshold,
/// false on the other); either end may be the larger one. Units are the caller's.
pub fn bisect<T>(mut pass: T, mut fail: T, steps: usize, holds: impl Fn(T) -> bool) -> T
where
    T: Copy + Add<Output = T> + Mul<Output = T> + From<f32>,
{
    let half = T::from(0.5);
    for _ in 0..steps {
        let mid = half * (pass + fail);
        if holds(mid) {
            pass = mid;
        } else {
            fail = mid;
        }
    }
    pass
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The threshold of `x ≥ √2` from above and of `x ≤ √2` from below, to the bracket's
    /// resolution after the steps, always on the side where the predicate holds.
    #[test]
    fn finds_the_threshold_from_either_side() {
        let t = 2f64.sqrt();
        let above = bisect(2.0, 1.0, 50, |x: f64| x >= t);
        assert!(above >= t && above - t < 1e-14, "{above}");
        let below = bisect(1.0f64, 2.0, 50, |x| x <= t);
        assert!(below <= t && t - below < 1e-14, "{below}");
        let single = bisect(2.0f32, 1.0, 30, |x: f32| x * x >= 2.0);
        assert!(single * single >= 2.0 && (single - 2f32.sqrt()).abs() < 1e-6);
        assert_eq!(bisect(3.0, 0.0, 0, |_: f64| true), 3.0);
    }
}
