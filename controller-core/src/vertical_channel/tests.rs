//! The vertical saturation: its range, its monotonicity and its smoothness at the origin.

use proptest::prelude::*;

use super::VerticalChannel;

proptest! {
    /// `ubar_p,z` lies in `(−M_down, M_up)`, is strictly decreasing in its argument (so `σ_z`
    /// is strictly increasing, what Theorem 1's cross term needs) and has the sign of `−y`.
    #[test]
    fn the_vertical_feedback_is_bounded_and_monotone(
        up in 0.1..15.0f64, down in 0.1..9.0f64, a in -100.0..100.0f64, b in -100.0..100.0f64,
    ) {
        let v = VerticalChannel { up, down, kf: 1.0, ks: 2.0 };
        let (fa, fb) = (v.feedback(a), v.feedback(b));
        prop_assert!(fa >= -down && fa <= up);
        prop_assert!(v.contains(fa));
        prop_assert!(fa * a <= 0.0);
        if a < b {
            prop_assert!(fa >= fb);
        }
        prop_assert_eq!(v.clamp(fa), fa);
    }
}

/// The two sides meet to second order at 0: slope −1 and no curvature from either side, so
/// `σ_z` is twice continuously differentiable and its linearisation is the paper's.
#[test]
fn the_two_sides_meet_smoothly() {
    let v = VerticalChannel {
        up: 8.0f64,
        down: 1.0,
        kf: 1.0,
        ks: 2.0,
    };
    let h = 1e-4f64;
    let slope_up = (v.feedback(-h) - v.feedback(0.0)) / -h;
    let slope_down = (v.feedback(h) - v.feedback(0.0)) / h;
    assert!((slope_up + 1.0).abs() < 1e-6 && (slope_down + 1.0).abs() < 1e-6);
    let curvature =
        |s: f64| (v.feedback(s * h) - 2.0 * v.feedback(0.0) + v.feedback(-s * h)) / (h * h);
    assert!(curvature(1.0).abs() < 1e-3, "{}", curvature(1.0));
    assert!(VerticalChannel {
        up: 0.0,
        down: 1.0,
        kf: 1.0,
        ks: 2.0
    }
    .validate()
    .is_err());
}
