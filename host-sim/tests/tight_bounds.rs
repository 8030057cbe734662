//! Tight a-priori bounds (`host_sim::tight_bounds`): the enclosures contain controller-core's
//! values, the bounds are below the paper's, and they grow with `M_p`.

use controller_core::attitude_control::AttitudeGains;
use controller_core::desired_attitude::desired_attitude;
use controller_core::mrp::rotation_from_mrp;
use controller_core::{
    certify, FilterStart, Gains, Limits, ReferenceTrajectory, Trajectory, Vehicle,
};
use host_sim::tight_bounds::confining_set::{ConfiningSet, SPLIT_DIM};
use host_sim::tight_bounds::desired_rates::{desired_rates, Heading};
use host_sim::tight_bounds::interval::Interval;
use host_sim::tight_bounds::torque::AttitudeTerm;
use host_sim::tight_bounds::{tight_bounds, TightOptions};
use nalgebra::{Vector2, Vector3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// controller-core's `(ω_d, ω̇_d)` at `u, u̇, ü` and the heading angle `ψ, ψ̇, ψ̈`.
fn reference(
    u: [f64; 3],
    ud: [f64; 3],
    udd: [f64; 3],
    psi: [f64; 3],
) -> (Vector3<f64>, Vector3<f64>) {
    let nu = Vector2::new(psi[0].cos(), psi[0].sin());
    let perp = Vector2::new(-nu.y, nu.x);
    let d = desired_attitude(
        &Vector3::from(u),
        &Vector3::from(ud),
        &Vector3::from(udd),
        &nu,
        &(perp * psi[1]),
        &(perp * psi[2] - nu * (psi[1] * psi[1])),
    )
    .unwrap();
    (d.angular_velocity, d.angular_acceleration)
}

fn uniform(rng: &mut ChaCha8Rng, x: Interval) -> f64 {
    x.lo + (x.hi - x.lo) * rng.random::<f64>()
}

fn paper_set() -> ConfiningSet {
    ConfiningSet::new(
        &Vehicle::paper(),
        &Gains::paper(),
        &ReferenceTrajectory::paper_helix().constants(),
        FilterStart::Zero,
    )
    .unwrap()
}

/// The closed form of `desired_rates` on `f64` equals controller-core's chain at random points
/// of a set wider than the paper's (any heading angle, larger rates).
#[test]
fn point_evaluation_matches_controller_core() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for _ in 0..20_000 {
        let mut r = |a: f64, b: f64| a + (b - a) * rng.random::<f64>();
        let u = [r(-4.0, 4.0), r(-4.0, 4.0), r(0.5, 14.0)];
        let ud = [r(-9.0, 9.0), r(-9.0, 9.0), r(-9.0, 9.0)];
        let udd = [r(-200.0, 200.0), r(-200.0, 200.0), r(-200.0, 200.0)];
        let psi = [r(-7.0, 7.0), r(-3.0, 3.0), r(-5.0, 5.0)];
        let (w, wd) = reference(u, ud, udd, psi);
        let h = Heading {
            cos: psi[0].cos(),
            sin: psi[0].sin(),
            rate: psi[1],
            acceleration: psi[2],
        };
        let mine = desired_rates(&u, &ud, &udd, &h);
        let scale = 1.0 + w.norm() + wd.norm();
        for i in 0..3 {
            assert!(
                (mine.angular_velocity[i] - w[i]).abs() < 1e-11 * scale,
                "{mine:?} {w}"
            );
            assert!(
                (mine.angular_acceleration[i] - wd[i]).abs() < 1e-11 * scale,
                "{mine:?} {wd}"
            );
        }
    }
}

/// Interval enclosures over random sub-boxes of the paper's confining set contain
/// controller-core's values at random points of the boxes.
#[test]
fn interval_enclosure_contains_controller_core_values() {
    let set = paper_set();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for _ in 0..2_000 {
        // A random sub-box of relative size 10^[-6, 0] in each variable.
        let scale = 10f64.powf(-6.0 * rng.random::<f64>());
        let region: [Interval; SPLIT_DIM] = core::array::from_fn(|j| {
            let x = set.split[j];
            let w = (x.hi - x.lo) * scale;
            let lo = x.lo + (x.hi - x.lo - w) * rng.random::<f64>();
            Interval::new(lo, lo + w)
        });
        let y = [
            Interval::symmetric(set.u_ddot),
            Interval::symmetric(set.u_ddot),
            Interval::symmetric(set.u_ddot),
            Interval::symmetric(set.heading_acceleration),
        ]
        .map(|x| {
            let w = (x.hi - x.lo) * scale;
            let lo = x.lo + (x.hi - x.lo - w) * rng.random::<f64>();
            Interval::new(lo, lo + w)
        });
        let (cos, sin) = region[6].cos_sin();
        let h = Heading {
            cos,
            sin,
            rate: region[7],
            acceleration: y[3],
        };
        let enc = desired_rates(
            &[region[0], region[1], region[2]],
            &[region[3], region[4], region[5]],
            &[y[0], y[1], y[2]],
            &h,
        );
        for _ in 0..20 {
            let x: [f64; SPLIT_DIM] = core::array::from_fn(|j| uniform(&mut rng, region[j]));
            let p: [f64; 4] = core::array::from_fn(|j| uniform(&mut rng, y[j]));
            let (w, wd) = reference(
                [x[0], x[1], x[2]],
                [x[3], x[4], x[5]],
                [p[0], p[1], p[2]],
                [x[6], x[7], p[3]],
            );
            for i in 0..3 {
                assert!(
                    enc.angular_velocity[i].contains(w[i]),
                    "{:?} {w}",
                    enc.angular_velocity
                );
                assert!(
                    enc.angular_acceleration[i].contains(wd[i]),
                    "{:?} {wd}",
                    enc.angular_acceleration
                );
            }
        }
    }
}
