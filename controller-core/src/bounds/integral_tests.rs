//! `certify` with the integral action on (extension, docs/integral-action.md): the extended
//! Theorem 1 interval and Lemma 1 terms against a hand evaluation, their limit as `M_i → 0`,
//! and the refusal of a level that lets the thrust vanish.

use super::tests::{paper, Hand};
use super::*;
use crate::reference::{ReferenceTrajectory, Trajectory};
use approx::assert_relative_eq;

fn integral_gains(level: f64) -> crate::integral::IntegralGains<f64> {
    crate::integral::IntegralGains {
        feedforward_scale: None,
        gain: 2.0,
        level: Vector3::new(0.5, 0.6, 1.5) * level,
        rate: Vector3::new(0.3, 0.4, 1.2),
        bandwidth: 5.0,
        observer: None,
    }
}

fn with_integral(level: f64) -> Certificate<f64> {
    let mut g = Gains::paper();
    g.integral = Some(integral_gains(level));
    certify(
        &Vehicle::paper(),
        &Limits::paper(),
        &g,
        &ReferenceTrajectory::paper_helix().constants(),
        FilterStart::Zero,
    )
    .unwrap()
}

/// The extended Theorem 1 interval and Lemma 1 terms, recomputed by hand from
/// docs/integral-action.md's formulas for the paper's set-up with M_i = (0.5, 0.6, 1.5).
#[test]
fn extended_bounds_match_a_hand_evaluation() {
    let Hand {
        m,
        g,
        mp,
        kf,
        ks,
        ka12,
        ka3,
        kj,
        kss,
        ..
    } = Hand::paper();
    let (lx, ly, lz) = (2.5f64, 2.6f64, 3.5f64);
    let tmin = m * (g - ka3 - lz);
    let tmax = m * (((lx * lx + ly * ly).sqrt() + ka12).powi(2) + (g + ka3 + lz).powi(2)).sqrt();
    let ke: f64 = 5.0;
    // Reachable-set bound per axis: min(2 k_η M_i, c (R_i + 16 ε M_i / 0.001 s)),
    // c = x/(1 − e^−x), x = k_η · 0.01 s; here every axis takes the reachable one (0.3 < 2·5·0.5,
    // ...).
    let x: f64 = ke * 0.01;
    let c = x / (1.0 - (-x).exp());
    let levels = [0.5, 0.6, 1.5];
    let rates = [0.3, 0.4, 1.2];
    let rate_bound: Vec<f64> = (0..3)
        .map(|i| {
            let reachable = c * (rates[i] + 16.0 * f64::EPSILON * levels[i] / 0.001);
            assert!(reachable < 2.0 * ke * levels[i]);
            reachable
        })
        .collect();
    let rate_term = rate_bound.iter().map(|b| b * b).sum::<f64>().sqrt();
    let acceleration_term = ke
        * (0..3)
            .map(|i| (rate_bound[i] + rates[i]).powi(2))
            .sum::<f64>()
            .sqrt();
    let ul = (kf / ks).powf(kf / (ks - kf));
    let uud = 2.0 * 3f64.sqrt() * kf * ul * mp + kj + rate_term;
    let uudd = 2.0 * 3f64.sqrt() * kf * mp * (kf * ul + ks) + kss + acceleration_term;
    let a = tmin / m;
    let lxy = (lx * lx + ly * ly).sqrt();
    let lw = a / (a * a + (lxy + ka12).powi(2)).sqrt();
    let c = with_integral(1.0);
    let b = c.bounds;
    assert_relative_eq!(b.thrust_min, tmin, max_relative = 1e-14);
    assert_relative_eq!(b.thrust_max, tmax, max_relative = 1e-14);
    assert_relative_eq!(b.u_rate, uud, max_relative = 1e-14);
    assert_relative_eq!(b.u_acceleration, uudd, max_relative = 1e-14);
    assert_relative_eq!(b.heading_projection_min, lw, max_relative = 1e-14);
    assert_relative_eq!(
        b.thrust_direction_rate,
        m * uud / tmin,
        max_relative = 1e-14
    );
    let i = c.integral.unwrap();
    assert_relative_eq!(i.u_rate_term, rate_term, max_relative = 1e-14);
    assert_eq!(c.conditions[5].rhs, lz);
}

/// As M_i → 0 the extended bounds tend to the paper's (T_max to a bound no larger than the
/// paper's: the split horizontal/vertical bound is tighter than eq:UpperBoundT's triangle
/// inequality), and the integral adds nothing when off.
#[test]
fn extended_bounds_reduce_to_the_papers() {
    let p = paper().bounds;
    assert!(paper().integral.is_none());
    let e = with_integral(1e-9).bounds;
    for (x, y) in [
        (e.thrust_min, p.thrust_min),
        (e.heading_projection_min, p.heading_projection_min),
        (e.angular_velocity, p.angular_velocity),
    ] {
        assert_relative_eq!(x, y, max_relative = 1e-8);
    }
    // The rate limit's term stays (k_η |R|), M_i's vanish.
    let ri = (0.09f64 + 0.16 + 1.44).sqrt();
    assert_relative_eq!(e.u_rate, p.u_rate, max_relative = 1e-8);
    assert_relative_eq!(
        e.u_acceleration,
        p.u_acceleration + 5.0 * ri,
        max_relative = 1e-8
    );
    assert!(e.thrust_max <= p.thrust_max);
    // Bigger levels only widen the bounds.
    let w = with_integral(1.0).bounds;
    assert!(w.thrust_min < p.thrust_min && w.thrust_max > e.thrust_max);
    assert!(w.angular_acceleration > p.angular_acceleration);
}

#[test]
fn refuses_an_integral_level_that_lets_the_thrust_vanish() {
    let mut g = Gains::<f64>::paper();
    let mut i = integral_gains(1.0);
    i.level.z = 8.0;
    g.integral = Some(i);
    let k = ReferenceTrajectory::paper_helix().constants();
    let e = certify(
        &Vehicle::paper(),
        &Limits::paper(),
        &g,
        &k,
        FilterStart::Zero,
    )
    .unwrap_err();
    match e {
        ParameterError::OutOfRange {
            name, value, high, ..
        } => {
            assert!(name.starts_with("M_p + M_i_z"));
            assert_eq!(value, 10.0);
            assert_relative_eq!(high, 9.81 - k.vertical_acceleration);
        }
        other => panic!("{other:?}"),
    }
}
