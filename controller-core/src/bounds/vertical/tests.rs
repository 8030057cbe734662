//! The vertical channel's bounds against the law: at random states of the set the filters keep
//! (any `u_f`, `u_s` in it, any `ubar_p` the feedback can take) on the paper's helix, the law's
//! own `u`, `u̇`, `ü`, `ρ̇`, `ρ̈` across `ρ`, `ω_d` and `ω̇_d` stay within `certify`'s bounds;
//! along closed-loop runs from the filters at rest too; and a large `M_up` leaves the thrust
//! floor and the thrust-direction rates of a small `M_down`.

use nalgebra::Vector3;
use proptest::prelude::*;

use crate::bounds::{certify, Certificate, FilterStart};
use crate::desired_attitude::desired_attitude;
use crate::gains::Gains;
use crate::position::FilterState;
use crate::position_saturation::PositionSaturation;
use crate::reference::{ReferenceTrajectory, Trajectory};
use crate::vertical_channel::VerticalChannel;
use crate::{Lemma1Form, Limits, Vehicle};

fn gains(
    shape: PositionSaturation,
    (mp, up, down): (f64, f64, f64),
    kf: f64,
    ks: f64,
) -> Gains<f64> {
    gains_z(shape, (mp, up, down), (kf, ks), (kf, ks))
}

fn gains_z(
    shape: PositionSaturation,
    (mp, up, down): (f64, f64, f64),
    (kf, ks): (f64, f64),
    (kf_z, ks_z): (f64, f64),
) -> Gains<f64> {
    let mut g = Gains::<f64>::paper();
    g.position.saturation = mp;
    g.position.saturation_shape = shape;
    g.position.kf = kf;
    g.position.ks = ks;
    g.position.vertical = Some(VerticalChannel {
        up,
        down,
        kf: kf_z,
        ks: ks_z,
    });
    g.lemma1 = Lemma1Form::Tangential;
    g
}

fn certify_with(g: &Gains<f64>, start: FilterStart) -> Certificate<f64> {
    certify(
        &Vehicle::paper(),
        &Limits::paper(),
        g,
        &ReferenceTrajectory::paper_helix().constants(),
        start,
    )
    .unwrap()
}

fn unit3() -> impl Strategy<Value = Vector3<f64>> {
    (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64).prop_map(|(x, y, z)| Vector3::new(x, y, z))
}

/// A point of the set `ubar_p` takes its values in, from a draw in the unit cube.
fn in_set(g: &Gains<f64>, d: &Vector3<f64>) -> Vector3<f64> {
    let p = &g.position;
    let v = p.vertical.unwrap();
    let mut h = Vector3::new(d.x, d.y, 0.0) * p.saturation;
    if p.saturation_shape == PositionSaturation::Norm && h.norm() > p.saturation {
        h *= p.saturation / h.norm();
    }
    let z = if d.z >= 0.0 { d.z * v.up } else { d.z * v.down };
    Vector3::new(h.x, h.y, z)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(6_000))]

    /// Given random levels (a braking `M_up` up to 12 m/s²), filters, filter states anywhere in
    /// the set and a random point of the helix, when the law evaluates its position loop and
    /// desired attitude, then every quantity is within `certify`'s bounds with the filters
    /// started anywhere in the set.
    #[test]
    fn the_laws_values_stay_within_the_bounds(
        norm in proptest::bool::ANY,
        mp in 0.3..4.0f64, up in 0.3..12.0f64, down in 0.2..6.0f64,
        kf in 0.3..8.0f64, ratio in 1.0..10.0f64, kf_z in 0.3..15.0f64, ratio_z in 1.0..10.0f64,
        uf in unit3(), us in unit3(), y in unit3(), scale in prop_oneof![0.0..2.0f64, 0.0..200.0f64],
        t in 0.0..15.0f64,
    ) {
        let shape = if norm { PositionSaturation::Norm } else { PositionSaturation::Componentwise };
        let g = gains_z(shape, (mp, up, down), (kf, ratio * kf), (kf_z, ratio_z * kf_z));
        let b = certify_with(&g, FilterStart::InSaturationBox).bounds;
        let p = &g.position;
        let filter = FilterState { u_f: in_set(&g, &uf), u_s: in_set(&g, &us) };
        // z₁, z₂ for ṽ = 0 from a chosen argument y of σ_p: k_p z₁ + k_v z₂ = y·scale.
        let (_, z2) = p.z_coordinates(&Vector3::zeros(), &Vector3::zeros(), &filter);
        let target = y * scale;
        let pe = (target - z2 * p.kv) / p.kp - filter.u_f / (p.kf * p.ks);
        let r = ReferenceTrajectory::<f64>::paper_helix().sample(t);
        let out = p.evaluate(None, &pe, &Vector3::zeros(), &filter, &r.acceleration, &r.jerk, &r.snap, 9.81);
        let m = Vehicle::<f64>::paper().mass;
        let tol = |x: f64| x * (1.0 + 1e-9) + 1e-12;
        prop_assert!(p.contains(&out.ubar_p));
        prop_assert!(m * out.u.norm() >= b.thrust_min * (1.0 - 1e-9));
        prop_assert!(m * out.u.norm() <= tol(b.thrust_max));
        prop_assert!(out.u_dot.norm() <= tol(b.u_rate));
        prop_assert!(out.u_ddot.norm() <= tol(b.u_acceleration));
        let d = desired_attitude(&out.u, &out.u_dot, &out.u_ddot, &r.heading, &r.heading_rate, &r.heading_acceleration)
            .expect("u points up");
        let rho = d.thrust_direction;
        let across = rho.acceleration - rho.unit * rho.unit.dot(&rho.acceleration);
        prop_assert!(rho.rate.norm() <= tol(b.thrust_direction_rate), "{} > {}", rho.rate.norm(), b.thrust_direction_rate);
        prop_assert!(across.norm() <= tol(b.thrust_direction_acceleration_projected));
        prop_assert!(rho.acceleration.norm() <= tol(b.thrust_direction_acceleration));
        prop_assert!(d.angular_velocity.norm() <= tol(b.angular_velocity));
        prop_assert!(d.angular_acceleration.norm() <= tol(b.angular_acceleration));
    }
}

/// Given the same horizontal level and `M_down`, when `M_up` grows from 1 to 10 m/s², then the
/// thrust floor does not move, `T_max` grows by `m` times the difference at most, and the
/// thrust-direction rate bound grows far less than with a symmetric level of 10 m/s² (which
/// `certify` refuses anyway: 10 > g).
#[test]
fn a_braking_level_keeps_the_floor_and_little_of_the_tilt_rate() {
    let low = certify_with(
        &gains(PositionSaturation::Norm, (2.0, 1.0, 1.0), 2.0, 6.0),
        FilterStart::Zero,
    )
    .bounds;
    let high = certify_with(
        &gains(PositionSaturation::Norm, (2.0, 10.0, 1.0), 2.0, 6.0),
        FilterStart::Zero,
    )
    .bounds;
    let m = Vehicle::<f64>::paper().mass;
    assert_eq!(low.thrust_min, high.thrust_min);
    assert!(high.thrust_max - low.thrust_max <= 9.0 * m + 1e-12);
    assert!(
        high.thrust_direction_rate < 3.0 * low.thrust_direction_rate,
        "{} vs {}",
        high.thrust_direction_rate,
        low.thrust_direction_rate
    );
    // The paper's symmetric level cannot brake at 10 m/s²: M_p must stay below g − K_a3.
    let mut sym = gains(PositionSaturation::Norm, (10.0, 10.0, 10.0), 2.0, 6.0);
    sym.position.vertical = None;
    assert!(certify(
        &Vehicle::paper(),
        &Limits::paper(),
        &sym,
        &ReferenceTrajectory::paper_helix().constants(),
        FilterStart::Zero
    )
    .is_err());
}
