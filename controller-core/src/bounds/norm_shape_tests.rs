//! `certify` with the norm-saturated position feedback (extension, docs/position-saturation.md):
//! Theorem 1 and Lemma 1 with `M_p` in place of `√3 M_p` and `√2 M_p`, evaluated by hand; never
//! looser than the paper's shape; and sound along closed-loop position runs that sample the
//! states the law reaches (random starts, the paper's helix, an ideal attitude loop).

use super::tests::Hand;
use super::*;
use crate::desired_attitude::desired_attitude;
use crate::position::{FilterState, PositionGains};
use crate::position_saturation::PositionSaturation;
use crate::reference::{ReferenceTrajectory, Trajectory};
use approx::assert_relative_eq;
use nalgebra::Vector3;
use proptest::prelude::*;

fn norm_gains() -> Gains<f64> {
    let mut g = Gains::paper();
    g.position.saturation_shape = PositionSaturation::Norm;
    g
}

fn certify_with(gains: &Gains<f64>, start: FilterStart) -> Certificate<f64> {
    certify(
        &Vehicle::paper(),
        &Limits::paper(),
        gains,
        &ReferenceTrajectory::paper_helix().constants(),
        start,
    )
    .unwrap()
}

/// Given Table I with the norm shape, when certified, then Theorem 1 and Lemma 1 are the
/// paper's formulas with `M_p` for `√3 M_p` (thrust, `U_u̇`, `U_ü`) and for `√2 M_p` (`L_ϖ`),
/// written out here from the formulas, not read from the code.
#[test]
fn theorem1_and_lemma1_match_a_hand_evaluation() {
    let Hand {
        m,
        g,
        mp,
        kf,
        ks,
        f,
        ka12,
        ka3,
        kj,
        kss,
    } = Hand::paper();
    use core::f64::consts::PI;
    let (knd, kndd) = (PI * f, PI * PI * f * f);
    let tmin = m * (g - mp - ka3);
    let tmax = m * (mp + (ka12 * ka12 + (ka3 + g).powi(2)).sqrt());
    let r = kf / ks;
    let ul = r.powf(r / (1.0 - r));
    let udot = 2.0 * kf * ul * mp + kj;
    let uddot = 2.0 * kf * mp * (kf * ul + ks) + kss;
    let rho_d = m * udot / tmin;
    let rho_dd = m * uddot / tmin + 3.0 * rho_d * rho_d;
    let a = tmin / m;
    let l_w = a / (a * a + (mp + ka12).powi(2)).sqrt();
    let ups_d = (rho_d + knd) / l_w;
    let ups_dd = (rho_dd + 2.0 * rho_d * knd + kndd) / l_w + 3.0 * ups_d * ups_d;
    let wd = (rho_d * rho_d + ups_d * ups_d).sqrt();
    let wdd = rho_d * ups_d + (rho_dd * rho_dd + ups_dd * ups_dd).sqrt();

    let b = certify_with(&norm_gains(), FilterStart::Zero).bounds;
    assert_relative_eq!(b.thrust_min, tmin, max_relative = 1e-12);
    assert_relative_eq!(b.thrust_max, tmax, max_relative = 1e-12);
    assert_relative_eq!(b.u_rate, udot, max_relative = 1e-12);
    assert_relative_eq!(b.u_acceleration, uddot, max_relative = 1e-12);
    assert_relative_eq!(b.heading_projection_min, l_w, max_relative = 1e-12);
    assert_relative_eq!(b.angular_velocity, wd, max_relative = 1e-10);
    assert_relative_eq!(b.angular_acceleration, wdd, max_relative = 1e-10);
}

/// Given the same gains, when the shape is the norm one, then no bound is looser than the
/// paper's shape, with and without the integral action, and T_min is the same (the vertical
/// level is M_p in both).
#[test]
fn the_norm_shape_is_never_looser() {
    let mut with_integral = Gains::paper();
    with_integral.position.saturation = 1.0;
    with_integral.integral = Some(crate::IntegralGains {
        gain: 2.0,
        level: nalgebra::Vector3::new(0.3, 0.3, 0.8),
        rate: nalgebra::Vector3::new(0.3, 0.3, 0.8),
        bandwidth: 4.0,
        observer: None,
        feedforward_scale: None,
    });
    for paper in [Gains::paper(), with_integral] {
        let mut norm = paper;
        norm.position.saturation_shape = PositionSaturation::Norm;
        for start in [FilterStart::Zero, FilterStart::InSaturationBox] {
            let (p, n) = (
                certify_with(&paper, start).bounds,
                certify_with(&norm, start).bounds,
            );
            assert_eq!(n.thrust_min, p.thrust_min);
            assert!(n.thrust_max < p.thrust_max);
            assert!(n.u_rate < p.u_rate && n.u_acceleration < p.u_acceleration);
            assert!(n.heading_projection_min > p.heading_projection_min);
            assert!(n.angular_velocity < p.angular_velocity);
            assert!(n.angular_acceleration < p.angular_acceleration);
            for i in 0..3 {
                assert!(n.torque_max[i] < p.torque_max[i]);
            }
        }
    }
}

/// One closed-loop run of the position law with the norm shape on the point-mass plant
/// `p̈ = u − g e₃` (the attitude loop ideal: the thrust vector is `m u`), sampled every `h`:
/// the largest `T/m`, `|u̇|`, `|ü|`, `|ω_d|`, `|ω̇_d|` and the smallest `T/m` seen.
struct Extremes {
    accel_min: f64,
    accel_max: f64,
    u_rate: f64,
    u_acceleration: f64,
    angular_velocity: f64,
    angular_acceleration: f64,
}

fn fly(gains: &PositionGains<f64>, p0: Vector3<f64>, v0: Vector3<f64>, t0: f64) -> Extremes {
    let reference = ReferenceTrajectory::paper_helix();
    let g = 9.81;
    let h = 0.002;
    let propagator = gains.propagator(h);
    let (mut p, mut v, mut filter) = (p0, v0, FilterState::zero());
    let mut e = Extremes {
        accel_min: f64::INFINITY,
        accel_max: 0.0,
        u_rate: 0.0,
        u_acceleration: 0.0,
        angular_velocity: 0.0,
        angular_acceleration: 0.0,
    };
    for n in 0..6000 {
        let r = reference.sample(t0 + n as f64 * h);
        let out = gains.evaluate(
            None,
            &(p - r.position),
            &(v - r.velocity),
            &filter,
            &r.acceleration,
            &r.jerk,
            &r.snap,
            g,
        );
        let d = desired_attitude(
            &out.u,
            &out.u_dot,
            &out.u_ddot,
            &r.heading,
            &r.heading_rate,
            &r.heading_acceleration,
        )
        .expect("u points up");
        e.accel_min = e.accel_min.min(out.u.norm());
        e.accel_max = e.accel_max.max(out.u.norm());
        e.u_rate = e.u_rate.max(out.u_dot.norm());
        e.u_acceleration = e.u_acceleration.max(out.u_ddot.norm());
        e.angular_velocity = e.angular_velocity.max(d.angular_velocity.norm());
        e.angular_acceleration = e.angular_acceleration.max(d.angular_acceleration.norm());
        // Semi-implicit Euler on the point mass, exact filter propagation.
        v += (out.u - Vector3::z() * g) * h;
        p += v * h;
        filter = propagator.apply(&filter, &out.ubar_p);
    }
    e
}

fn v3(r: f64) -> impl Strategy<Value = Vector3<f64>> {
    (-r..r, -r..r, -r..r).prop_map(|(a, b, c)| Vector3::new(a, b, c))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]
    /// Given random starts (up to 30 m and 15 m/s off) and random filter and level choices,
    /// when the norm-shaped law flies the paper's helix, then every sample stays inside the
    /// norm shape's Theorem 1 interval and Lemma 1 bounds (0 samples above them).
    #[test]
    fn norm_shape_bounds_hold_along_closed_loop_runs(
        p0 in v3(30.0), v0 in v3(15.0), t0 in 0.0..15.0f64,
        kf in 0.5..6.0f64, ratio in 1.5..10.0f64, mp in 0.5..6.0f64,
    ) {
        let mut gains = norm_gains();
        gains.position.kf = kf;
        gains.position.ks = ratio * kf;
        gains.position.saturation = mp;
        let b = certify_with(&gains, FilterStart::Zero).bounds;
        let m = Vehicle::<f64>::paper().mass;
        let e = fly(&gains.position, p0, v0, t0);
        let tol = 1.0 + 1e-9;
        prop_assert!(e.accel_min * m * tol >= b.thrust_min);
        prop_assert!(e.accel_max * m <= b.thrust_max * tol);
        prop_assert!(e.u_rate <= b.u_rate * tol);
        prop_assert!(e.u_acceleration <= b.u_acceleration * tol);
        prop_assert!(e.angular_velocity <= b.angular_velocity * tol);
        prop_assert!(e.angular_acceleration <= b.angular_acceleration * tol);
    }
}

/// Given a run whose feedback saturates hard in a diagonal direction (a start 30 m off on all
/// three axes), when flown with the paper's componentwise shape, then its thrust exceeds the
/// norm shape's `T_max` for the same `M_p`: the √3 the norm shape removes is reached by the
/// paper's law, so the norm shape's smaller bound is not a property of every law.
#[test]
fn the_componentwise_shape_reaches_beyond_the_norm_bound() {
    let norm = certify_with(&norm_gains(), FilterStart::Zero).bounds;
    let paper = Gains::<f64>::paper();
    let e = fly(
        &paper.position,
        Vector3::new(-30.0, -30.0, -30.0),
        Vector3::zeros(),
        0.0,
    );
    let m = Vehicle::<f64>::paper().mass;
    assert!(
        e.accel_max * m > norm.thrust_max,
        "{} <= {}",
        e.accel_max * m,
        norm.thrust_max
    );
}
