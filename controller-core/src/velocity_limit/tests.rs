use super::*;
use crate::position::PositionGains;
use crate::saturation::tanh_saturation;
use crate::vertical_channel::VerticalChannel;
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
        vertical: None,
    }
}

/// The same gains with the vertical channel apart: braking level `M_up = 3 m/s²` up, `M_down =
/// 1 m/s²` down.
fn vertical_gains() -> PositionGains<f64> {
    PositionGains {
        vertical: Some(VerticalChannel {
            up: 3.0,
            down: 1.0,
            kf: 0.6,
            ks: 0.8,
        }),
        ..gains()
    }
}

/// [`limit`] with the vertical profile braking at 0.7 of each vertical level.
fn vertical_limit() -> VelocityLimit<f64> {
    VelocityLimit {
        vertical: Some(VerticalBraking { up: 2.1, down: 0.7 }),
        ..limit()
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
        g.feedback_of(&limit().argument((g.kp, g.kv), &z1, &z2)),
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

/// Given `V ≤ 0`, a non-finite `V`, `a ≤ 0` or `a ≥ M_p`, then validation refuses it by name;
/// with the vertical channel apart, so are a vertical braking outside its level, a missing one,
/// and one given without the channel.
#[test]
fn validation_names_the_bad_value() {
    let bad = |speed, braking| {
        VelocityLimit {
            speed,
            braking,
            vertical: None,
        }
        .validate(1.0, None)
        .unwrap_err()
    };
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
    assert!(limit().validate(1.0, None).is_ok());

    let channel = vertical_gains().vertical;
    let vertical_bad = |up, down| {
        VelocityLimit {
            vertical: Some(VerticalBraking { up, down }),
            ..limit()
        }
        .validate(1.0, channel.as_ref())
        .unwrap_err()
    };
    assert!(matches!(
        vertical_bad(3.0, 0.5),
        ParameterError::OutOfRange { name: "braking_up", value, high, .. } if value == 3.0 && high == 3.0
    ));
    assert!(matches!(
        vertical_bad(2.0, 1.2),
        ParameterError::OutOfRange { name: "braking_down", high, .. } if high == 1.0
    ));
    assert!(matches!(
        vertical_bad(2.0, -0.1),
        ParameterError::NotPositive {
            name: "braking_down",
            ..
        }
    ));
    assert!(matches!(
        limit().validate(1.0, channel.as_ref()).unwrap_err(),
        ParameterError::OutOfRange { name: "braking_up", value, high, .. } if value == 0.0 && high == 3.0
    ));
    assert!(matches!(
        vertical_limit().validate(1.0, None).unwrap_err(),
        ParameterError::OutOfRange { name: "braking_up", high, .. } if high == 0.0
    ));
    assert!(vertical_limit().validate(1.0, channel.as_ref()).is_ok());
}

/// Given the vertical braking accelerations, then above the reference the vertical profile is
/// the profile braking at `a_up`, below it the one braking at `a_down` (stopping distances
/// against the kinetic identity on each side), continuous through 0 with the slope `c`, and
/// the horizontal components keep `a`.
#[test]
fn the_vertical_profile_brakes_at_each_sides_level() {
    let l = vertical_limit();
    let b = l.vertical.unwrap();
    let c = 1.0;
    // Beyond both linear zones (`a_up/c²` = 2.1 m) and below the speed limit on both sides.
    for x in [3.0, 5.0, 6.5] {
        let above = l.vertical_profile(x, c);
        let below = l.vertical_profile(-x, c);
        assert_relative_eq!(
            above * above / (2.0 * b.up) + b.up / (2.0 * c * c),
            x,
            epsilon = 1e-12
        );
        assert_relative_eq!(
            below * below / (2.0 * b.down) + b.down / (2.0 * c * c),
            x,
            epsilon = 1e-12
        );
        assert!(below < 0.0 && above > -below);
    }
    let tiny = 1e-9;
    assert_relative_eq!(l.vertical_profile(tiny, c), c * tiny, epsilon = 1e-20);
    assert_relative_eq!(l.vertical_profile(-tiny, c), -c * tiny, epsilon = 1e-20);
    let z1 = Vector3::new(4.0, -4.0, 4.0);
    let arg = l.argument((1.0, 1.0), &z1, &Vector3::zeros());
    assert_eq!(arg.x, limit().profile(4.0, c));
    assert_eq!(arg.y, limit().profile(-4.0, c));
    assert_eq!(arg.z, l.vertical_profile(4.0, c));
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
        g.feedback_of(&l.argument((g.kp, g.kv), &one(z1), &one(z2)))
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

/// Given the vertical channel apart (`M_up = 3`, `M_down = 1 m/s²`) and its braking profile,
/// when the vertical z-subsystem falls from 200 m below the reference at 30 m/s down (a flip),
/// then it brakes at about the upward level (not at the horizontal `M_p = 1 m/s²`) and
/// converges; and from 200 m above or below at rest it comes back without crossing the
/// reference by more than the profile's slack.
#[test]
fn a_fall_brakes_with_the_vertical_channels_upward_level() {
    let (g, l) = (vertical_gains(), vertical_limit());
    let up = |x: f64| Vector3::new(0.0, 0.0, x);
    let vertical = |z1: f64, z2: f64| g.feedback_of(&l.argument((g.kp, g.kv), &up(z1), &up(z2))).z;
    let (end, lowest) = fly(vertical, -200.0, -30.0, 300.0);
    // Braking from 30 m/s takes 30²/(2 M_up) = 150 m at the upward level (the least any braking
    // within it can take), 450 m at M_p: it brakes at no less than 0.95 M_up on average.
    let fall = -200.0 - lowest;
    let up_level = g.vertical.unwrap().up;
    // (`tanh` rounds to exactly 1 for large arguments: at most the level, to the integration's
    // rounding.)
    assert!(
        fall > 30.0 * 30.0 / (2.0 * up_level) - 1e-6,
        "fell only {fall} m"
    );
    assert!(
        fall < 30.0 * 30.0 / (2.0 * 0.95 * up_level),
        "fell {fall} m"
    );
    // From above, the descent brakes at a_up; from below (the axis mirrored, so that the
    // helper's lowest point is the highest one), the climb brakes at a_down.
    let (_, lowest_from_above) = fly(vertical, 200.0, 0.0, 300.0);
    assert!(
        lowest_from_above > -1.0,
        "from above, down to {lowest_from_above} m"
    );
    let (_, mirrored) = fly(|z1, z2| -vertical(-z1, -z2), 200.0, 0.0, 300.0);
    assert!(mirrored > -1.0, "from below, up to {} m", -mirrored);
    assert!(end.0.abs() < 0.01 && end.1.abs() < 0.01, "ends at {end:?}");
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
        let l = VelocityLimit { speed, braking: frac * m, vertical: None };
        let u = g.feedback_of(&l.argument((g.kp, g.kv), &Vector3::from(z1), &Vector3::from(z2)));
        // `≤`: tanh rounds to exactly 1 for large arguments, in f64 as in the paper's law.
        prop_assert!(u.iter().all(|c| c.abs() <= m));
        let c = g.kp / g.kv;
        prop_assert!(l.profile(x + dx, c) >= l.profile(x, c));
        prop_assert_eq!(l.profile(-x, c), -l.profile(x, c));
        prop_assert!(l.profile(x, c).abs() <= speed);
    }

    /// With the vertical channel apart: the horizontal components stay within `M_p`, the
    /// vertical one within `[−M_down, M_up]` (what the vertical channel's certificate uses), and
    /// the vertical profile is non-decreasing, has the sign of its argument and stays within
    /// `±V`, whatever the two braking shares.
    #[test]
    fn vertical_feedback_keeps_each_level(
        z1 in prop::array::uniform3(-1e4..1e4f64),
        z2 in prop::array::uniform3(-1e3..1e3f64),
        x in -1e4..1e4f64,
        dx in 0.0..10.0f64,
        speed in 0.1..30.0f64,
        (share_up, share_down) in (0.01..0.99f64, 0.01..0.99f64),
        (m, up, down) in (0.1..5.0f64, 0.1..8.0f64, 0.1..5.0f64),
    ) {
        let g = PositionGains {
            saturation: m,
            vertical: Some(VerticalChannel { up, down, kf: 0.6, ks: 0.8 }),
            ..gains()
        };
        let l = VelocityLimit {
            speed,
            braking: 0.5 * m,
            vertical: Some(VerticalBraking { up: share_up * up, down: share_down * down }),
        };
        prop_assert!(l.validate(m, g.vertical.as_ref()).is_ok());
        let u = g.feedback_of(&l.argument((g.kp, g.kv), &Vector3::from(z1), &Vector3::from(z2)));
        prop_assert!(u.x.abs() <= m && u.y.abs() <= m);
        prop_assert!(u.z <= up && u.z >= -down);
        let c = g.kp / g.kv;
        let (at, next) = (l.vertical_profile(x, c), l.vertical_profile(x + dx, c));
        prop_assert!(next >= at);
        prop_assert!(at * x >= 0.0);
        prop_assert!(at.abs() <= speed);
    }
}
