use super::*;
use crate::reference::ReferenceSample;
use proptest::prelude::*;

fn gains() -> FeedforwardScaleGains<f64> {
    FeedforwardScaleGains {
        gain: 0.5,
        excitation: 0.1,
        level: 0.25,
        rate: 0.2,
        tracking_limit: 0.05,
    }
}

fn v3(r: f64) -> impl Strategy<Value = Vector3<f64>> {
    (-r..r, -r..r, -r..r).prop_map(|(a, b, c)| Vector3::new(a, b, c))
}

fn sample(a: Vector3<f64>, j: Vector3<f64>, s: Vector3<f64>) -> ReferenceSample<f64> {
    let mut r = ReferenceSample::hold(Vector3::zeros(), 0.0);
    r.acceleration = a;
    r.jerk = j;
    r.snap = s;
    r
}

proptest! {
    /// Whatever drives it (estimates and reference accelerations of any size, held for long,
    /// sample lengths up to 0.5 s, freezing), μ and μ_f stay in [−μ̄, μ̄], μ̇ within ±R_μ, and
    /// μ̇_f, μ̈_f within the bounds the certificate's constants use.
    #[test]
    fn estimate_never_leaves_its_bounds(
        drive in proptest::collection::vec((v3(100.0), v3(20.0)), 1..400),
        h in 0.0005..0.5f64,
        gain in 0.01..20.0f64,
        bandwidth in 0.01..100.0f64,
        frozen_from in 0usize..400,
    ) {
        let f = FeedforwardScaleGains { gain, ..gains() };
        let (b, a) = (f.filtered_rate_bound(bandwidth), f.filtered_acceleration_bound(bandwidth));
        let mut s = FeedforwardScaleState::zero();
        for (k, (moving, acc)) in drive.iter().enumerate() {
            let frozen = k >= frozen_from;
            let rate = f.rate_of(&s, moving, acc, &Vector3::zeros(), frozen);
            prop_assert!(rate.abs() <= f.rate);
            let reference = sample(*acc, Vector3::zeros(), Vector3::zeros());
            let out = f.output(&s, rate, bandwidth, &reference);
            // With jerk and snap zero, u_dot = μ̇_f a and u_ddot = μ̈_f a.
            let (mu_dot, mu_ddot) = (out.u_dot.norm() / acc.norm(), out.u_ddot.norm() / acc.norm());
            if acc.norm() > 1e-3 {
                prop_assert!(mu_dot <= b * (1.0 + 1e-9), "|mu_f dot| {mu_dot} > {b}");
                prop_assert!(mu_ddot <= a * (1.0 + 1e-9), "|mu_f ddot| {mu_ddot} > {a}");
            }
            let next = f.advance(&s, rate, bandwidth, h);
            prop_assert!(next.estimate.abs() <= f.level && next.filtered.abs() <= f.level);
            if frozen {
                prop_assert_eq!(next.estimate, s.estimate);
            }
            s = next;
        }
    }

    /// The scaled feedforward (1 + μ_f) p̈_d and its first two derivatives, for any state of the
    /// estimate and any reference inside its constants, lie inside the constants
    /// `FeedforwardScaleGains::constants` gives the certificate.
    #[test]
    fn scaled_reference_stays_inside_its_constants(
        acc in v3(2.0), jerk in v3(3.0), snap in v3(5.0),
        mu in -0.25..0.25f64, gap in -1.0..1.0f64, rate_frac in -1.0..1.0f64,
        bandwidth in 0.1..50.0f64,
    ) {
        let f = gains();
        let k = TrajectoryConstants {
            horizontal_acceleration: acc.xy().norm(),
            vertical_acceleration: acc.z.abs(),
            jerk: jerk.norm(),
            snap: snap.norm(),
            heading_rate: 0.0,
            heading_acceleration: 0.0,
        };
        // A state the advance step can reach: |μ − μ_f| within b/k_η.
        let b = f.filtered_rate_bound(bandwidth);
        let filtered = (mu + gap * b / bandwidth).clamp(-f.level, f.level);
        let s = FeedforwardScaleState { estimate: mu, filtered };
        let rate = rate_frac * f.rate;
        let out = f.output(&s, rate, bandwidth, &sample(acc, jerk, snap));
        let scaled = f.constants(&k, bandwidth);
        let (a, j, sn) = (acc + out.u, jerk + out.u_dot, snap + out.u_ddot);
        let tol = 1.0 + 1e-12;
        prop_assert!(a.xy().norm() <= scaled.horizontal_acceleration * tol + 1e-15);
        prop_assert!(a.z.abs() <= scaled.vertical_acceleration * tol + 1e-15);
        prop_assert!(j.norm() <= scaled.jerk * tol + 1e-15);
        prop_assert!(sn.norm() <= scaled.snap * tol + 1e-15);
    }
}

/// On a helix's acceleration, a turning part of the estimate `η − η_f` that is a fixed fraction
/// of p̈_d (what a mass error leaves) drives μ towards the sign of that fraction; a constant one
/// (a constant force while η is still moving towards it) leaves μ where it started after whole
/// turns, to rounding.
#[test]
fn mass_error_moves_the_estimate_and_a_constant_force_does_not() {
    let f = FeedforwardScaleGains {
        rate: 10.0,
        level: 0.5,
        ..gains()
    };
    let omega = 0.5_f64;
    let acc = |t: f64| Vector3::new(-(omega * t).cos(), -(omega * t).sin(), 0.0) * 0.3;
    let h = 0.01;
    let turn = (2.0 * core::f64::consts::PI / omega / h).round() as usize;
    let run = |moving: &dyn Fn(f64) -> Vector3<f64>| {
        let mut s = FeedforwardScaleState::zero();
        for k in 0..turn * 4 {
            let t = k as f64 * h;
            let r = f.rate_of(&s, &moving(t), &acc(t), &Vector3::zeros(), false);
            s = f.advance(&s, r, 1.0, h);
        }
        s.estimate
    };
    // A plant heavier than modelled: η rises along p̈_d, so η − η_f is +c p̈_d.
    let heavier = run(&|t| acc(t) * 0.8);
    assert!(heavier > 0.05, "mu = {heavier}");
    let lighter = run(&|t| acc(t) * -0.8);
    assert!(lighter < -0.05, "mu = {lighter}");
    // Small enough that μ's swing within a turn stays inside its level (in closed loop this
    // part of η − η_f vanishes once η has taken the force).
    let force = run(&|_| Vector3::new(0.02, -0.01, 0.05));
    assert!(force.abs() < 1e-3 * heavier, "mu = {force}");
}

#[test]
fn hover_reference_never_moves_the_estimate() {
    let f = gains();
    let s = FeedforwardScaleState::zero();
    let zero = Vector3::zeros();
    let rate = f.rate_of(&s, &Vector3::new(5.0, -3.0, 40.0), &zero, &zero, false);
    assert_eq!(rate, 0.0);
}

/// Far from the reference (a transient) the estimate is held, whatever drives it; near it, the
/// same drive moves it.
#[test]
fn estimate_is_held_outside_the_tracking_limit() {
    let f = gains();
    let s = FeedforwardScaleState::zero();
    let (moving, acc) = (Vector3::new(0.1, 0.0, 0.0), Vector3::new(0.3, 0.0, 0.0));
    let near = Vector3::new(0.04, -0.05, 0.0);
    let far = Vector3::new(0.0, 0.051, 0.0);
    assert!(f.rate_of(&s, &moving, &acc, &near, false) > 0.0);
    assert_eq!(f.rate_of(&s, &moving, &acc, &far, false), 0.0);
}

#[test]
fn refuses_bad_gains_by_name() {
    for (bad, name) in [
        (
            FeedforwardScaleGains {
                level: 1.0,
                ..gains()
            },
            "mu_level",
        ),
        (
            FeedforwardScaleGains {
                level: 0.0,
                ..gains()
            },
            "mu_level",
        ),
        (
            FeedforwardScaleGains {
                rate: f64::NAN,
                ..gains()
            },
            "mu_rate",
        ),
        (
            FeedforwardScaleGains {
                gain: -1.0,
                ..gains()
            },
            "mu_gain",
        ),
        (
            FeedforwardScaleGains {
                excitation: 0.0,
                ..gains()
            },
            "mu_excitation",
        ),
        (
            FeedforwardScaleGains {
                tracking_limit: -1.0,
                ..gains()
            },
            "mu_tracking_limit",
        ),
    ] {
        let got = match bad.validate() {
            Err(ParameterError::NotPositive { name, .. })
            | Err(ParameterError::OutOfRange { name, .. }) => name,
            other => panic!("{other:?}"),
        };
        assert_eq!(got, name);
    }
}
