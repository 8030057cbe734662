//! The tangential form of Lemma 1 against the law it bounds: each inequality of its argument
//! holds at random signals (with the signals' own magnitudes in place of the `U` constants),
//! its constants are attained, and `certify` with it is the paper's chain with those constants.

use nalgebra::{Vector2, Vector3};
use proptest::prelude::*;

use super::Lemma1Form;
use crate::desired_attitude::{desired_attitude, normalize_with_derivatives};
use crate::reference::Trajectory;
use crate::{certify, FilterStart, Gains, Limits, ReferenceTrajectory, Vehicle};

/// Lemma 1's chain with one form's coefficients, evaluated on magnitudes:
/// `r = |u̇|/|u|`, `q = |ü|/|u|`, `(K_ν̇, K_ν̈)` and `L = |ϖ|`. Returns `U_ω̇d`.
fn chain(form: Lemma1Form, r: f64, q: f64, heading: (f64, f64), l: f64) -> f64 {
    let c = form.coefficients::<f64>();
    let rho_dd_projected = q + c.projected * r * r;
    let ups_d = (r + heading.0) / l;
    let ups_dd =
        (rho_dd_projected + 2.0 * r * heading.0 + heading.1) / l + c.projected * ups_d * ups_d;
    r * ups_d + (rho_dd_projected * rho_dd_projected + ups_dd * ups_dd).sqrt()
}

fn vec3() -> impl Strategy<Value = Vector3<f64>> {
    (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64).prop_map(|(x, y, z)| Vector3::new(x, y, z))
}

/// `(u, u̇, ü)` with `u` upward, at scales from calm to violent, and a unit heading with its
/// first two derivatives `(ψ, ψ̇, ψ̈)`.
fn signals() -> impl Strategy<Value = (Vector3<f64>, Vector3<f64>, Vector3<f64>, [f64; 3])> {
    (
        vec3(),
        0.2..10.0f64,
        vec3(),
        prop_oneof![Just(0.0), 0.01..1.0f64, 1.0..30.0f64],
        vec3(),
        prop_oneof![Just(0.0), 0.01..1.0f64, 1.0..300.0f64],
        (-3.2..3.2f64, -3.0..3.0f64, -5.0..5.0f64),
    )
        .prop_map(|(u, uz, ud, sd, udd, sdd, (psi, psid, psidd))| {
            let u = Vector3::new(3.0 * u.x, 3.0 * u.y, uz + u.z.abs());
            (u, ud * sd, udd * sdd, [psi, psid, psidd])
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(20_000))]

    /// Given random `(u, u̇, ü)` and heading signals, when the law's `ω̇_d` is computed, then
    /// each step of the tangential argument holds with the signals' own magnitudes, and
    /// `|ω̇_d|` is below the tangential chain, itself below the paper's.
    #[test]
    fn every_step_of_the_tangential_chain_holds((u, ud, udd, [psi, psid, psidd]) in signals()) {
        let (s, c) = psi.sin_cos();
        let heading = Vector2::new(c, s);
        let heading_rate = Vector2::new(-s, c) * psid;
        let heading_acceleration = Vector2::new(-s, c) * psidd - heading * (psid * psid);
        let d = desired_attitude(&u, &ud, &udd, &heading, &heading_rate, &heading_acceleration)
            .expect("u is upward and the heading is a unit vector");
        let (n, rho) = (u.norm(), d.thrust_direction);
        let (r, q) = (ud.norm() / n, udd.norm() / n);
        let tol = |x: f64| 1e-9 * (1.0 + x);
        // |P_ρ ρ̈| ≤ q + r² and |ρ̈| ≤ q + (2/√3) r².
        let projected = rho.acceleration - rho.unit * rho.unit.dot(&rho.acceleration);
        prop_assert!(projected.norm() <= q + r * r + tol(q + r * r));
        let whole = q + 2.0 / 3f64.sqrt() * r * r;
        prop_assert!(rho.acceleration.norm() <= whole + tol(whole));
        // |P_υ ϋ| ≤ |ϖ̈|/|ϖ| + (|ϖ̇|/|ϖ|)², with ϖ rebuilt as desired_attitude builds it.
        let nu = Vector3::new(heading.x, heading.y, 0.0);
        let nu_d = Vector3::new(heading_rate.x, heading_rate.y, 0.0);
        let nu_dd = Vector3::new(heading_acceleration.x, heading_acceleration.y, 0.0);
        let (p, pd, pdd) = (rho.unit, rho.rate, rho.acceleration);
        let varpi_of = |a: Vector3<f64>, b: f64| Vector3::new(a.x, a.y, -b);
        let varpi = varpi_of(nu * p.z, p.dot(&nu));
        let varpi_d = varpi_of(nu * pd.z + nu_d * p.z, pd.dot(&nu) + p.dot(&nu_d));
        let varpi_dd = varpi_of(
            nu * pdd.z + nu_d * (2.0 * pd.z) + nu_dd * p.z,
            pdd.dot(&nu) + 2.0 * pd.dot(&nu_d) + p.dot(&nu_dd),
        );
        let ups = normalize_with_derivatives(&varpi, &varpi_d, &varpi_dd).expect("ϖ ≠ 0");
        let l = varpi.norm();
        let ups_perp = ups.acceleration - ups.unit * ups.unit.dot(&ups.acceleration);
        let ups_bound = varpi_dd.norm() / l + (varpi_d.norm() / l).powi(2);
        prop_assert!(ups_perp.norm() <= ups_bound + tol(ups_bound));
        // |P_υ ϖ̈| ≤ |P_ρ ρ̈| + 2|ρ̇||ν̇_d| + |ν̈_d|: ρ̈'s radial part drops out across υ.
        let varpi_dd_perp = varpi_dd - ups.unit * ups.unit.dot(&varpi_dd);
        let across = projected.norm()
            + 2.0 * pd.norm() * heading_rate.norm()
            + heading_acceleration.norm();
        prop_assert!(varpi_dd_perp.norm() <= across + tol(across));
        let ups_bound = varpi_dd_perp.norm() / l + (varpi_d.norm() / l).powi(2);
        prop_assert!(ups_perp.norm() <= ups_bound + tol(ups_bound));
        // The whole chain, with the signals' magnitudes as its constants.
        let k = (heading_rate.norm(), heading_acceleration.norm());
        let tangential = chain(Lemma1Form::Tangential, r, q, k, l);
        let paper = chain(Lemma1Form::Paper, r, q, k, l);
        let w = d.angular_acceleration.norm();
        prop_assert!(w <= tangential + tol(tangential), "|ω̇_d| {w} above {tangential}");
        prop_assert!(tangential <= paper);
    }
}

/// Given `ü = 0` and `u̇` at the angle where `|ρ̇|² = 2|u̇|²/(3|u|²)`, when `ρ̈` is computed,
/// then `|ρ̈|` is exactly `(2/√3)(|u̇|/|u|)²`; at 45°, `|P_ρ ρ̈| = (|u̇|/|u|)²`: neither
/// coefficient of the tangential form can be lowered.
#[test]
fn the_tangential_coefficients_are_attained() {
    let u = Vector3::new(0.0, 0.0, 2.0);
    let r = 1.5;
    let c = Lemma1Form::Tangential.coefficients::<f64>();
    for (b2, expect_whole) in [(2.0 / 3.0, true), (0.5, false)] {
        let (b, a) = (r * f64::sqrt(b2), r * f64::sqrt(1.0 - b2));
        let ud = Vector3::new(b, 0.0, a) * u.norm();
        let rho = normalize_with_derivatives(&u, &ud, &Vector3::zeros()).expect("u ≠ 0");
        let projected = rho.acceleration - rho.unit * rho.unit.dot(&rho.acceleration);
        if expect_whole {
            approx::assert_relative_eq!(rho.acceleration.norm(), c.whole * r * r, epsilon = 1e-12);
        } else {
            approx::assert_relative_eq!(projected.norm(), c.projected * r * r, epsilon = 1e-12);
        }
    }
}

/// Given the paper's set-up, when it is certified with each form, then the tangential
/// certificate differs only in `U_ρ̈`, `U_ϋ`, `U_ω̇d` and what they feed, equals a hand
/// evaluation of the chain from the paper's own `U_ρ̇`, `U_υ̇`, and is below the paper's.
#[test]
fn certify_with_the_tangential_form_is_the_chain_with_its_coefficients() {
    let constants = ReferenceTrajectory::paper_helix().constants();
    let with = |form| {
        let mut g = Gains::<f64>::paper();
        g.lemma1 = form;
        certify(
            &Vehicle::paper(),
            &Limits::paper(),
            &g,
            &constants,
            FilterStart::Zero,
        )
        .expect("the paper's set-up is accepted")
        .bounds
    };
    let (paper, tangential) = (with(Lemma1Form::Paper), with(Lemma1Form::Tangential));
    assert_eq!(paper, with(Lemma1Form::default()));
    assert_eq!(paper.thrust_min, tangential.thrust_min);
    assert_eq!(paper.thrust_max, tangential.thrust_max);
    assert_eq!(paper.angular_velocity, tangential.angular_velocity);
    assert_eq!(paper.heading_axis_rate, tangential.heading_axis_rate);
    let rho_d = paper.thrust_direction_rate;
    let q = paper.thrust_direction_acceleration - 3.0 * rho_d * rho_d;
    let (l, ups_d) = (paper.heading_projection_min, paper.heading_axis_rate);
    let projected = q + rho_d * rho_d;
    let ups_dd =
        (projected + 2.0 * rho_d * constants.heading_rate + constants.heading_acceleration) / l
            + ups_d * ups_d;
    approx::assert_relative_eq!(
        tangential.thrust_direction_acceleration,
        q + 2.0 / 3f64.sqrt() * rho_d * rho_d,
        max_relative = 1e-12
    );
    let expected = rho_d * ups_d + (projected * projected + ups_dd * ups_dd).sqrt();
    approx::assert_relative_eq!(
        tangential.angular_acceleration,
        expected,
        max_relative = 1e-12
    );
    approx::assert_relative_eq!(
        tangential.heading_axis_acceleration,
        ups_dd,
        max_relative = 1e-12
    );
    assert!(tangential.angular_acceleration < 0.8 * paper.angular_acceleration);
    for i in 0..3 {
        assert!(tangential.torque_max[i] < paper.torque_max[i]);
    }
    assert!(tangential.assumption.angular_acceleration < paper.assumption.angular_acceleration);
}
