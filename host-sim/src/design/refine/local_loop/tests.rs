use super::*;
use crate::design::variables::{AttitudeLaw, Choices};

fn layout(local: bool) -> Layout {
    Layout {
        law: AttitudeLaw::TiltPriority,
        local,
        vertical: true,
        narrow_local: true,
        local_vertical: true,
        turn_over: true,
        local_integral: false,
    }
}

fn apart() -> Layout {
    Layout {
        local_integral: true,
        ..layout(true)
    }
}

/// A design found so far at `0.4` in every coordinate, with cost `cost`.
fn found(local: bool, cost: f64) -> Optimum {
    Optimum {
        x: vec![0.4; layout(local).dimension()],
        cost,
        evaluations: 960,
    }
}

/// The local loop's frequency, damping and integral frequency of a whole point laid out as
/// `l`, read from the choices the point maps to (not from the module's own index arithmetic).
fn loop_of(x: &[f64], l: Layout) -> (f64, f64, Option<f64>) {
    let local = Choices::from_unit(x, l).local.unwrap();
    (
        local.position_frequency_rad_s,
        local.position_damping,
        local.integral_frequency_rad_s,
    )
}

/// Given a cost whose minimum over the local loop is at a grid point (the third frequency, the
/// third damping) and that is only met with the integral held apart at the design's frequency,
/// when the design is polished, then exactly that point is kept: the frequency
/// `0.5 · 16^(2/3)` rad/s, the damping 1.2, the integral at the design's `ω_p,L`; every other
/// choice as before, the layout the one that holds the integral apart, and the 16 grid
/// evaluations counted.
#[test]
fn the_lowest_grid_point_of_the_local_loop_is_kept_with_the_integral_held() {
    let before = found(true, 10.0);
    let (w0, _, none) = loop_of(&before.x, layout(true));
    assert_eq!(none, None);
    let target = (0.5 * 16f64.powf(2.0 / 3.0), 1.2);
    let cost = |x: &[f64], l: Layout| {
        let (w, z, wi) = loop_of(x, l);
        let held = wi.map_or(1.0, |wi| (wi - w0).abs());
        (w.ln() - target.0.ln()).powi(2) + (z - target.1).powi(2) + held
    };
    let (best, kept_layout, r) = refine_local_loop(&cost, before.clone(), layout(true));
    let r = r.unwrap();
    assert!(r.kept, "{r:?}");
    assert_eq!(kept_layout, apart());
    assert_eq!(best.x.len(), apart().dimension());
    assert_eq!(apart().dimension(), layout(true).dimension() + 1);
    let (w, z, wi) = loop_of(&best.x, apart());
    assert!(
        (w - target.0).abs() < 1e-9 && (z - target.1).abs() < 1e-9,
        "{w} {z}"
    );
    assert_eq!(wi, Some(w0));
    assert!(best.cost < 1e-18 && best.cost == r.refined);
    assert_eq!(cost(&best.x, apart()), best.cost);
    let (a, b) = (
        Choices::from_unit(&before.x, layout(true)),
        Choices::from_unit(&best.x, apart()),
    );
    let (la, lb) = (a.local.unwrap(), b.local.unwrap());
    assert_eq!(la.kf_ratio, lb.kf_ratio);
    assert_eq!(la.ks_ratio, lb.ks_ratio);
    assert_eq!(la.tilt_out_deg, lb.tilt_out_deg);
    assert_eq!(la.saturation_fraction, lb.saturation_fraction);
    assert_eq!(la.vertical_kf_ratio, lb.vertical_kf_ratio);
    assert_eq!(a.tilt, b.tilt);
    assert_eq!(a.vertical, b.vertical);
    assert_eq!(
        (a.kf, a.position_frequency_rad_s),
        (b.kf, b.position_frequency_rad_s)
    );
    assert_eq!(r.evaluations, FREQUENCY_POINTS * DAMPING_POINTS);
    assert_eq!(best.evaluations, 960 + r.evaluations);
}

/// Given a cost that every grid point ties (and NaN at the grid's first point), when polished,
/// the first finite lowest point in frequency-major order is the refinement's, and it is not
/// kept when it does not score below the design found so far.
#[test]
fn ties_go_to_the_first_point_and_nothing_is_kept_unless_lower() {
    let cost = |x: &[f64], l: Layout| {
        let (w, z, _) = loop_of(x, l);
        if (w - 0.5).abs() < 1e-9 && (z - 0.6).abs() < 1e-9 {
            f64::NAN
        } else {
            2.0
        }
    };
    let (best, kept_layout, r) = refine_local_loop(&cost, found(true, 2.0), layout(true));
    let r = r.unwrap();
    assert!(!r.kept && r.refined == 2.0, "{r:?}");
    assert_eq!(best.x, found(true, 2.0).x);
    assert_eq!(kept_layout, layout(true));
    assert_eq!(best.evaluations, 960 + FREQUENCY_POINTS * DAMPING_POINTS);
    let (best, l, r) = refine_local_loop(&cost, found(true, 3.0), layout(true));
    assert!(r.unwrap().kept && l == apart());
    let (w, z, _) = loop_of(&best.x, l);
    assert!((w - 0.5).abs() < 1e-9 && (z - 0.9).abs() < 1e-9, "{w} {z}");
}

/// Given a design without a local regime, one that already holds the integral apart, or one
/// that misses a constraint, there is nothing to polish: the design is returned as it was and
/// no evaluation is spent.
#[test]
fn no_local_regime_or_a_missed_constraint_is_left_alone() {
    let cost = |_: &[f64], _: Layout| 0.0;
    let (best, l, r) = refine_local_loop(&cost, found(false, 1.0), layout(false));
    assert!(r.is_none() && l == layout(false) && best.evaluations == 960);
    let (best, l, r) = refine_local_loop(&cost, found(true, PENALTY), layout(true));
    assert!(r.is_none() && l == layout(true) && best.evaluations == 960);
    assert_eq!(best.x, found(true, PENALTY).x);
    let held = Optimum {
        x: vec![0.4; apart().dimension()],
        cost: 1.0,
        evaluations: 960,
    };
    let (best, l, r) = refine_local_loop(&cost, held, apart());
    assert!(r.is_none() && l == apart() && best.evaluations == 960);
}
