use super::*;
use crate::position::PositionGains;
use crate::saturation::tanh_saturation;
use approx::assert_relative_eq;
use nalgebra::Vector3;
use proptest::prelude::*;

fn gains() -> PositionGains<f64> {
    PositionGains {
        kp: 9.0,
        kv: 9.0,
        kf: 0.3,
        ks: 0.4,
        saturation: 1.0,
        saturation_shape: crate::position_saturation::PositionSaturation::Componentwise,
        vertical: None,
    }
}

fn limit() -> VelocityLimit<f64> {
    VelocityLimit {
        speed: 5.0,
        braking: 0.5,
    }
}

/// Given a small error (inside `a/c²` on every axis), when the feedback is evaluated, then it
/// is the paper's `−σ_p(k_p z₁ + k_v z₂)` to rounding.
#[test]
fn inside_the_linear_zone_it_is_the_papers_law() {
    let g = gains();
    let c = g.kp / g.kv;
    let reach = limit().braking / (c * c);
    let z1 = Vector3::new(0.9 * reach, -0.3 * reach, 0.0);
    let z2 = Vector3::new(-0.2, 0.7, 1.5);
    let paper = -tanh_saturation(&(z1 * g.kp + z2 * g.kv), g.saturation);
    assert_relative_eq!(
        limit().feedback((g.kp, g.kv), (g.saturation_shape, g.saturation), &z1, &z2),
        paper,
        epsilon = 1e-12
    );
}

/// Given the profile, then beyond the linear zone a vehicle braking at `a` from speed `φ(x)`
/// stops within `x` (the kinetic identity `φ² = 2a x − a²/c²` below the speed limit), and the
/// speed limit caps it.
#[test]
fn the_profile_brakes_at_a_and_is_capped() {
    let l = limit();
    let c = 1.0;
    for x in [1.0, 4.0, 20.0] {
        let phi = l.profile(x, c);
        // Stopping distance from φ at a, plus the linear zone's own distance a/(2c²).
        let stop = phi * phi / (2.0 * l.braking) + l.braking / (2.0 * c * c);
        assert_relative_eq!(stop, x, epsilon = 1e-12);
        assert_relative_eq!(l.profile(-x, c), -phi, epsilon = 0.0);
    }
    assert_eq!(l.profile(1e4, c), l.speed);
    assert_eq!(l.profile(-1e4, c), -l.speed);
}

/// Given `V ≤ 0`, a non-finite `V`, `a ≤ 0` or `a ≥ M_p`, then validation refuses it by name.
#[test]
fn validation_names_the_bad_value() {
    let bad = |speed, braking| VelocityLimit { speed, braking }.validate(1.0).unwrap_err();
    assert!(matches!(
        bad(0.0, 0.5),
        ParameterError::NotPositive {
            name: "speed_limit",
            ..
        }
    ));
    assert!(matches!(
        bad(f64::NAN, 0.5),
        ParameterError::NotPositive {
            name: "speed_limit",
            ..
        }
    ));
    assert!(matches!(
        bad(5.0, 0.0),
        ParameterError::NotPositive {
            name: "braking",
            ..
        }
    ));
    assert!(matches!(
        bad(5.0, 1.0),
        ParameterError::OutOfRange { name: "braking", high, .. } if high == 1.0
    ));
    assert!(limit().validate(1.0).is_ok());
}

/// Integrates one axis of the z-subsystem `ż₁ = z₂`, `ż₂ = ubar_p` (RK4, 10 ms) from `(z1, z2)`
/// for `seconds` and returns the final state and the smallest `z₁` on the way.
fn fly(feedback: impl Fn(f64, f64) -> f64, z1: f64, z2: f64, seconds: f64) -> ((f64, f64), f64) {
    let f = |s: (f64, f64)| (s.1, feedback(s.0, s.1));
    let (mut s, h) = ((z1, z2), 0.01);
    let mut lowest = z1;
    for _ in 0..(seconds / h) as usize {
        let k1 = f(s);
        let k2 = f((s.0 + 0.5 * h * k1.0, s.1 + 0.5 * h * k1.1));
        let k3 = f((s.0 + 0.5 * h * k2.0, s.1 + 0.5 * h * k2.1));
        let k4 = f((s.0 + h * k3.0, s.1 + h * k3.1));
        s.0 += h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
        s.1 += h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
        lowest = lowest.min(s.0);
    }
    (s, lowest)
}

/// Given a 500 m error falling away at 30 m/s (the x500 after a flip), when the z-subsystem
/// is flown with `M_p = 1 m/s²`, then the paper's feedback overshoots by hundreds of metres and
/// is still far off after 300 s, while the velocity-limited one brakes, comes back at the speed
/// limit without overshooting by more than the braking profile's slack, and has converged.
#[test]
fn from_a_long_fall_it_comes_back_without_the_papers_overshoot() {
    let (g, l) = (gains(), limit());
    let one = |x: f64| Vector3::new(x, 0.0, 0.0);
    let paper = |z1: f64, z2: f64| -tanh_saturation(&one(g.kp * z1 + g.kv * z2), g.saturation).x;
    let limited = |z1: f64, z2: f64| {
        l.feedback(
            (g.kp, g.kv),
            (g.saturation_shape, g.saturation),
            &one(z1),
            &one(z2),
        )
        .x
    };
    let (end_paper, lowest_paper) = fly(paper, 500.0, 30.0, 300.0);
    let (end_limited, lowest_limited) = fly(limited, 500.0, 30.0, 300.0);
    assert!(
        lowest_paper < -100.0,
        "paper overshoots to {lowest_paper} m"
    );
    assert!(end_paper.0.abs() > 50.0, "paper ends at {end_paper:?}");
    assert!(
        lowest_limited > -1.0,
        "limited overshoots to {lowest_limited} m"
    );
    assert!(
        end_limited.0.abs() < 0.01,
        "limited ends at {end_limited:?}"
    );
}

proptest! {
    /// Every component of the feedback stays within `M_p` (what Theorem 1 and Lemma 1 use),
    /// and the profile is odd, non-decreasing and within `±V`.
    #[test]
    fn feedback_keeps_the_saturation_level(
        z1 in prop::array::uniform3(-1e4..1e4f64),
        z2 in prop::array::uniform3(-1e3..1e3f64),
        x in -1e4..1e4f64,
        dx in 0.0..10.0f64,
        speed in 0.1..30.0f64,
        frac in 0.01..0.99f64,
        m in 0.1..5.0f64,
    ) {
        let g = PositionGains { saturation: m, ..gains() };
        let l = VelocityLimit { speed, braking: frac * m };
        let u = l.feedback((g.kp, g.kv), (g.saturation_shape, g.saturation), &Vector3::from(z1), &Vector3::from(z2));
        // `≤`: tanh rounds to exactly 1 for large arguments, in f64 as in the paper's law.
        prop_assert!(u.iter().all(|c| c.abs() <= m));
        let c = g.kp / g.kv;
        prop_assert!(l.profile(x + dx, c) >= l.profile(x, c));
        prop_assert_eq!(l.profile(-x, c), -l.profile(x, c));
        prop_assert!(l.profile(x, c).abs() <= speed);
    }
}
