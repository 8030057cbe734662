//! Tests of the waypoint path: the profile's peaks recomputed independently, the derivatives
//! against finite differences, continuity at the stops, the constants against dense sampling,
//! the timing limits, the slow-down search.

use super::*;
use approx::assert_relative_eq;
use proptest::prelude::*;

/// Coefficients (ascending powers) of φ and of its derivatives up to the fifth, computed here
/// from φ's own coefficients (not from the module's tables).
fn derivative_coefficients() -> [[f64; 10]; 7] {
    let mut out = [[0.0; 10]; 7];
    out[0] = [0.0, 0.0, 0.0, 0.0, 0.0, 126.0, -420.0, 540.0, -315.0, 70.0];
    for k in 1..7 {
        for i in 1..10 {
            out[k][i - 1] = i as f64 * out[k - 1][i];
        }
    }
    out
}

fn poly(c: &[f64; 10], s: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, a| acc * s + a)
}

/// Each `PEAK[k]` is an upper bound of `sup|φ⁽ᵏ⁺¹⁾|` on [0, 1] and within 1e-6 (relative) of
/// it: sampled every `h` = 1e-6, plus `h²/8` times a bound on the derivative two orders up (the
/// sum of its coefficients' magnitudes): at an interior maximum the slope is zero, so the
/// nearer sample, at most `h/2` away, is below it by at most `(h/2)² M / 2`.
#[test]
fn peaks_are_tight_upper_bounds() {
    let c = derivative_coefficients();
    let h = 1e-6;
    for k in 0..4 {
        let curvature: f64 = c[k + 3].iter().map(|a| a.abs()).sum();
        let sampled = (0..=1_000_000)
            .map(|n| poly(&c[k + 1], n as f64 * h).abs())
            .fold(0.0, f64::max);
        let sup_bound = sampled + h * h / 8.0 * curvature;
        assert!(
            profile::PEAK[k] >= sup_bound,
            "PEAK[{k}] = {} below {sup_bound}",
            profile::PEAK[k]
        );
        assert!(
            profile::PEAK[k] <= sampled * (1.0 + 1e-6),
            "PEAK[{k}] loose"
        );
    }
}

/// The profile: 0 → 1 with its first four derivatives zero at both ends, and `eval` agrees
/// with the independently derived coefficients.
#[test]
fn profile_is_rest_to_rest() {
    let c = derivative_coefficients();
    for s in [0.0, 1.0] {
        for (k, ck) in c.iter().enumerate().take(5).skip(1) {
            assert_eq!(poly(ck, s), 0.0, "derivative {k} at {s}");
        }
    }
    assert_eq!(poly(&c[0], 1.0), 1.0);
    for n in 0..=100 {
        let s = n as f64 / 100.0;
        let e = profile::eval(s);
        for k in 0..5 {
            assert_relative_eq!(e[k], poly(&c[k], s), epsilon = 1e-9, max_relative = 1e-12);
        }
    }
    assert_eq!(profile::eval(-0.5), [0.0; 5]);
    assert_eq!(profile::eval(1.5), [1.0, 0.0, 0.0, 0.0, 0.0]);
}

fn limits() -> PathLimits<f64> {
    PathLimits {
        speed: 1.5,
        acceleration: 2.0,
        yaw_rate: 1.0,
        min_duration: 0.5,
    }
}

fn square() -> WaypointPath<f64, 8> {
    let stop = |x: f64, y: f64, z: f64, yaw: f64, hold: f64| Stop {
        position: Vector3::new(x, y, z),
        yaw,
        hold,
    };
    WaypointPath::new(
        Vector3::new(0.0, 0.0, 0.0),
        0.0,
        &[
            stop(0.0, 0.0, 1.5, 0.0, 1.0),
            stop(2.0, 0.0, 1.5, 3.0, 0.0),
            stop(2.0, 2.0, 2.5, -3.0, 2.0),
            stop(2.0, 2.0, 2.5, -3.0, 1.0), // same place: a hold only
            stop(0.0, 0.0, 1.0, 1.0, 0.5),
        ],
        &limits(),
    )
    .expect("valid path")
}

/// Each derivative is the central difference of the one below it, inside legs and across
/// stops.
#[test]
fn derivatives_match_finite_differences() {
    let path = square();
    let h = 1e-5;
    let end = path.duration() + 1.0;
    for n in 0..400 {
        let t = -0.5 + end * n as f64 / 400.0;
        let (a, b, c) = (path.sample(t - h), path.sample(t), path.sample(t + h));
        let fd = |f: fn(&ReferenceSample<f64>) -> Vector3<f64>| (f(&c) - f(&a)) / (2.0 * h);
        assert_relative_eq!(fd(|s| s.position), b.velocity, epsilon = 1e-5);
        assert_relative_eq!(fd(|s| s.velocity), b.acceleration, epsilon = 1e-4);
        assert_relative_eq!(fd(|s| s.acceleration), b.jerk, epsilon = 1e-3);
        assert_relative_eq!(fd(|s| s.jerk), b.snap, epsilon = 1e-2);
        let fd2 = (c.heading - a.heading) / (2.0 * h);
        assert_relative_eq!(fd2, b.heading_rate, epsilon = 1e-5);
        let fd2 = (c.heading_rate - a.heading_rate) / (2.0 * h);
        assert_relative_eq!(fd2, b.heading_acceleration, epsilon = 1e-4);
    }
}

/// At every arrival the reference is at the stop, at rest, with zero acceleration, jerk and
/// snap on both sides (four times continuously differentiable), and the yaw is the stop's.
#[test]
fn stops_are_reached_at_rest() {
    let path = square();
    let eps = 1e-9;
    for i in 0..path.len() {
        let (p, yaw) = path.stop(i).expect("stop");
        for t in [
            path.arrival(i).expect("arrival"),
            path.departure(i).expect("departure"),
        ] {
            for s in [path.sample(t - eps), path.sample(t), path.sample(t + eps)] {
                assert_relative_eq!(s.position, p, epsilon = 1e-6);
                for v in [s.velocity, s.acceleration, s.jerk, s.snap] {
                    assert!(v.norm() < 1e-3, "not at rest at stop {i}: {v:?}");
                }
                assert_relative_eq!(s.yaw(), wrap_pi(yaw), epsilon = 1e-6);
            }
        }
    }
    // After the end: the last stop, for good.
    let (last, _) = path.stop(path.len() - 1).expect("stop");
    assert_eq!(path.sample(path.duration() + 100.0).position, last);
}

/// The yaw turns the short way round: from 3 rad to −3 rad is a 0.28 rad turn, not 6.
#[test]
fn yaw_turns_the_short_way() {
    let path = square();
    let (_, y1) = path.stop(1).expect("stop");
    let (_, y2) = path.stop(2).expect("stop");
    assert_relative_eq!(y2 - y1, 2.0 * core::f64::consts::PI - 6.0, epsilon = 1e-12);
}

/// Dense sampling of every leg: each constant bounds its quantity, the position ones are
/// attained (exact suprema, within the sampling), the speed, acceleration and yaw rate respect
/// the limits.
#[test]
fn constants_bound_and_are_attained() {
    let path = square();
    let k = path.constants();
    let mut seen = [0.0f64; 6];
    let (mut speed, mut accel, mut yaw_rate) = (0.0f64, 0.0f64, 0.0f64);
    let end = path.duration();
    for n in 0..=200_000 {
        let s = path.sample(end * n as f64 / 200_000.0);
        assert!(
            k.contain(&s, 1e-12),
            "sample outside the constants at n = {n}"
        );
        seen[0] = seen[0].max(s.acceleration.xy().norm());
        seen[1] = seen[1].max(s.acceleration.z.abs());
        seen[2] = seen[2].max(s.jerk.norm());
        seen[3] = seen[3].max(s.snap.norm());
        seen[4] = seen[4].max(s.heading_rate.norm());
        seen[5] = seen[5].max(s.heading_acceleration.norm());
        speed = speed.max(s.velocity.norm());
        accel = accel.max(s.acceleration.norm());
        yaw_rate = yaw_rate.max(s.heading_rate.norm());
    }
    for (name, bound, got) in [
        ("K_a12", k.horizontal_acceleration, seen[0]),
        ("K_a3", k.vertical_acceleration, seen[1]),
        ("K_j", k.jerk, seen[2]),
        ("K_s", k.snap, seen[3]),
        ("K_nu_dot", k.heading_rate, seen[4]),
    ] {
        assert!(
            got >= bound * 0.999,
            "{name}: sup {got} well below the bound {bound}"
        );
    }
    let l = limits();
    assert!(speed <= l.speed * (1.0 + 1e-9), "speed {speed}");
    assert!(
        accel <= l.acceleration * (1.0 + 1e-6),
        "acceleration {accel}"
    );
    assert!(yaw_rate <= l.yaw_rate * (1.0 + 1e-9), "yaw rate {yaw_rate}");
}

/// A slower timing's constants are the scaled constants, and its stops are the same.
#[test]
fn slowed_path_scales_its_constants() {
    let path = square();
    for c in [1.0, 1.3, 2.0, 7.5] {
        let slow = path.slowed(c);
        let (a, b) = (slow.constants(), path.constants().time_scaled(c));
        for (x, y) in [
            (a.horizontal_acceleration, b.horizontal_acceleration),
            (a.vertical_acceleration, b.vertical_acceleration),
            (a.jerk, b.jerk),
            (a.snap, b.snap),
            (a.heading_rate, b.heading_rate),
            (a.heading_acceleration, b.heading_acceleration),
        ] {
            assert_relative_eq!(x, y, max_relative = 1e-12);
        }
        for i in 0..path.len() {
            assert_eq!(slow.stop(i), path.stop(i));
        }
    }
    assert_eq!(path.slowed(0.5), path, "speeding up is not offered");
}

/// The slow-down search against the closed form: with the predicate `K_j ≤ j_max` the
/// smallest factor is `(K_j / j_max)^(1/3)`.
#[test]
fn slowdown_matches_the_closed_form() {
    let k = square().constants();
    let j_max = k.jerk / 5.0;
    let c = slowdown_to_certify(&k, 100.0, |k| k.jerk <= j_max).expect("certifiable");
    let exact = 5.0f64.cbrt();
    assert!(c >= exact && c <= exact * 1.01, "{c} vs {exact}");
    assert_eq!(slowdown_to_certify(&k, 100.0, |_| true), Some(1.0));
    assert_eq!(slowdown_to_certify(&k, 100.0, |_| false), None);
    assert_eq!(slowdown_to_certify(&k, 1.5, |k| k.jerk <= j_max), None);
}

/// Refusals: too many stops, a NaN stop, a negative hold, a bad limit.
#[test]
fn bad_input_is_refused() {
    let ok = Stop {
        position: Vector3::new(1.0, 0.0, 1.0),
        yaw: 0.0,
        hold: 0.0,
    };
    let start = Vector3::zeros();
    assert_eq!(
        WaypointPath::<f64, 2>::new(start, 0.0, &[ok; 3], &limits()),
        Err(PathError::TooManyStops { capacity: 2 })
    );
    let nan = Stop {
        position: Vector3::new(f64::NAN, 0.0, 0.0),
        ..ok
    };
    assert_eq!(
        WaypointPath::<f64, 4>::new(start, 0.0, &[ok, nan], &limits()),
        Err(PathError::BadStop { index: 1 })
    );
    let negative = Stop { hold: -1.0, ..ok };
    assert_eq!(
        WaypointPath::<f64, 4>::new(start, 0.0, &[negative], &limits()),
        Err(PathError::BadStop { index: 0 })
    );
    let bad = PathLimits {
        acceleration: 0.0,
        ..limits()
    };
    assert!(matches!(
        WaypointPath::<f64, 4>::new(start, 0.0, &[ok], &bad),
        Err(PathError::BadLimit {
            name: "acceleration",
            ..
        })
    ));
    let empty = WaypointPath::<f64, 4>::new(start, 0.5, &[], &limits()).expect("empty path");
    assert!(empty.is_empty());
    assert_eq!(empty.duration(), 0.0);
    assert_eq!(empty.constants(), TrajectoryConstants::zero());
    assert_eq!(empty.sample(3.0).position, start);
}

proptest! {
    /// Random paths in f32 (as flown on board): every sample lies within the constants (with
    /// f32 rounding slack), and the reference ends at the last stop.
    #[test]
    fn random_paths_stay_within_their_constants(
        stops in proptest::collection::vec(
            ((-20.0f32..20.0, -20.0f32..20.0, 0.0f32..10.0), -7.0f32..7.0, 0.0f32..2.0),
            0..12,
        ),
        speed in 0.2f32..8.0,
        acceleration in 0.2f32..10.0,
        yaw_rate in 0.1f32..3.0,
        factor in 1.0f32..4.0,
    ) {
        let stops: heapless_free::Stops = stops
            .iter()
            .map(|&((x, y, z), yaw, hold)| Stop { position: Vector3::new(x, y, z), yaw, hold })
            .collect();
        let limits = PathLimits { speed, acceleration, yaw_rate, min_duration: 0.2 };
        let path = WaypointPath::<f32, 12>::new(Vector3::new(1.0, -1.0, 0.5), 0.3, &stops, &limits)
            .expect("valid path")
            .slowed(factor);
        let k = path.constants();
        let end = path.duration();
        for n in 0..=3000 {
            let s = path.sample(end * n as f32 / 3000.0);
            prop_assert!(s.is_finite());
            prop_assert!(k.contain(&s, 1e-4), "sample {n} outside {k:?}: {s:?}");
        }
        if let Some(last) = stops.last() {
            prop_assert!((path.sample(end + 1.0).position - last.position).norm() < 1e-3);
        }
    }
}

/// A `Vec` alias for the property test's stop lists (the crate itself allocates nothing).
mod heapless_free {
    pub type Stops = std::vec::Vec<super::Stop<f32>>;
}
