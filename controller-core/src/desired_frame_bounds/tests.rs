//! The desired frame's per-axis bounds against the law they bound: at random signals the
//! components of the law's own `ω_d`, `ω̇_d` and gyroscopic term stay below the bounds computed
//! from the signals' own magnitudes, the closed form of `ω_d,3` is the law's, and `certify`'s
//! bounds are never above Lemma 1's norms.

use nalgebra::{Vector2, Vector3};
use proptest::prelude::*;

use super::{ChainBounds, DesiredFrameBounds};
use crate::desired_attitude::desired_attitude;
use crate::reference::{ReferenceTrajectory, Trajectory};
use crate::{certify, FilterStart, Gains, Lemma1Form, Limits, TrajectoryConstants, Vehicle};

pub(crate) fn vec3() -> impl Strategy<Value = Vector3<f64>> {
    (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64).prop_map(|(x, y, z)| Vector3::new(x, y, z))
}

/// `(u, u̇, ü)` with `u` upward (tilts up to about 80°), at scales from calm to violent, and a
/// unit heading with `(ψ, ψ̇, ψ̈)`, a constant heading a third of the time (also the compensated
/// heading's tests' signals).
pub(crate) fn signals(
) -> impl Strategy<Value = (Vector3<f64>, Vector3<f64>, Vector3<f64>, [f64; 3])> {
    (
        vec3(),
        0.5..10.0f64,
        vec3(),
        prop_oneof![Just(0.0), 0.01..1.0f64, 1.0..30.0f64],
        vec3(),
        prop_oneof![Just(0.0), 0.01..1.0f64, 1.0..300.0f64],
        (
            -3.2..3.2f64,
            prop_oneof![Just(0.0), -3.0..3.0f64],
            -5.0..5.0f64,
        ),
    )
        .prop_map(|(u, uz, ud, sd, udd, sdd, (psi, psid, psidd))| {
            let u = Vector3::new(6.0 * u.x, 6.0 * u.y, uz + u.z.abs());
            let psidd = if psid == 0.0 { 0.0 } else { psidd };
            (u, ud * sd, udd * sdd, [psi, psid, psidd])
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(8_000))]

    /// Given random `(u, u̇, ü)` and heading signals, when the law's `ω_d`, `ω̇_d` are computed,
    /// then each desired-frame component is below its bound evaluated with the signals' own
    /// magnitudes (`|ρ̇|`, `|P_ρ ρ̈|`, the horizontal share `|ρ_xy|`, `|ψ̇|`, `|ν̈|`), and so is
    /// each component of the gyroscopic term at `R̃ = I`.
    #[test]
    fn the_laws_components_stay_below_their_bounds((u, ud, udd, [psi, psid, psidd]) in signals()) {
        let (s, c) = psi.sin_cos();
        let heading = Vector2::new(c, s);
        let heading_rate = Vector2::new(-s, c) * psid;
        let heading_acceleration = Vector2::new(-s, c) * psidd - heading * (psid * psid);
        let d = desired_attitude(&u, &ud, &udd, &heading, &heading_rate, &heading_acceleration)
            .expect("u is upward and the heading is a unit vector");
        let rho = d.thrust_direction;
        let across = rho.acceleration - rho.unit * rho.unit.dot(&rho.acceleration);
        let h = rho.unit.xy().norm();
        let chain = ChainBounds {
            thrust_direction_rate: rho.rate.norm(),
            thrust_direction_acceleration_across: across.norm(),
            heading_projection_min: (1.0 - h * h).sqrt(),
            heading_rate: psid.abs(),
            heading_acceleration: heading_acceleration.norm(),
            angular_velocity: f64::INFINITY,
            angular_acceleration: f64::INFINITY,
        };
        let inertia = Vector3::new(0.0239, 0.0241, 0.044);
        let b = DesiredFrameBounds::new(&chain, &inertia);
        let (w, a) = (d.angular_velocity, d.angular_acceleration);
        let tol = |x: f64| 1e-9 * (1.0 + x.abs());
        prop_assert!(w.xy().norm() <= b.tilt_rate + tol(b.tilt_rate));
        prop_assert!(w.z.abs() <= b.yaw_rate + tol(b.yaw_rate), "{} vs {}", w.z, b.yaw_rate);
        prop_assert!(
            a.xy().norm() <= b.tilt_acceleration + tol(b.tilt_acceleration),
            "{} vs {}", a.xy().norm(), b.tilt_acceleration
        );
        prop_assert!(
            a.z.abs() <= b.yaw_acceleration + tol(b.yaw_acceleration),
            "{} vs {}", a.z, b.yaw_acceleration
        );
        let gyro = inertia.component_mul(&w).cross(&w);
        for i in 0..3 {
            prop_assert!(gyro[i].abs() <= b.gyroscopic[i] + tol(b.gyroscopic[i]));
        }
        // The norms the certified torque set takes: at most the components' hypotenuse, and
        // never above the cap they are given.
        let (wn, an) = b.norm_bounds((f64::INFINITY, f64::INFINITY));
        prop_assert!(w.norm() <= wn + tol(wn), "{} vs {}", w.norm(), wn);
        prop_assert!(a.norm() <= an + tol(an), "{} vs {}", a.norm(), an);
        let capped = b.norm_bounds((0.5 * wn, 0.5 * an));
        prop_assert!(capped == (0.5 * wn, 0.5 * an));
    }

    /// `ω_d,3 = (s det(ρ, ρ̇, k) + ψ̇ ρ₃)/(1 − s²)` with `k = (ν_d, 0) × e₃`, `s = ρᵀk`: the
    /// closed form the yaw bounds differentiate is the law's own yaw rate.
    #[test]
    fn the_yaw_rate_has_the_closed_form((u, ud, udd, [psi, psid, psidd]) in signals()) {
        let (s, c) = psi.sin_cos();
        let heading = Vector2::new(c, s);
        let heading_rate = Vector2::new(-s, c) * psid;
        let heading_acceleration = Vector2::new(-s, c) * psidd - heading * (psid * psid);
        let d = desired_attitude(&u, &ud, &udd, &heading, &heading_rate, &heading_acceleration)
            .expect("upward");
        let (p, pd) = (d.thrust_direction.unit, d.thrust_direction.rate);
        let k = Vector3::new(c, s, 0.0).cross(&Vector3::z());
        let sk = p.dot(&k);
        let closed = (sk * p.dot(&pd.cross(&k)) + psid * p.z) / (1.0 - sk * sk);
        let w3 = d.angular_velocity.z;
        prop_assert!((closed - w3).abs() <= 1e-9 * (1.0 + w3.abs()), "{closed} vs {w3}");
    }
}

/// Given a hover (constant heading) and a design's position gains, when `certify` runs, then
/// the desired frame's bounds are below Lemma 1's norms; the yaw rate is the tilt coupling
/// alone (the horizontal share times the tilt rate over `L_ϖ`), and with a small tilt range
/// (norm-saturated `M_p` = 1 m/s²: at most 7°) the yaw acceleration is a small part of the tilt
/// acceleration.
#[test]
fn at_hover_the_yaw_components_are_the_tilt_coupling() {
    let vehicle = Vehicle::<f64>::paper();
    let mut gains = Gains::<f64>::paper();
    gains.position.saturation = 1.0;
    gains.position.saturation_shape = crate::PositionSaturation::Norm;
    gains.position.kf = 4.0;
    gains.position.ks = 10.0;
    gains.lemma1 = Lemma1Form::Tangential;
    let hover = TrajectoryConstants::<f64>::zero();
    let c = certify(
        &vehicle,
        &Limits::paper(),
        &gains,
        &hover,
        FilterStart::Zero,
    )
    .unwrap();
    let (b, f) = (&c.bounds, &c.bounds.desired_frame);
    assert!(f.tilt_rate <= b.angular_velocity && f.yaw_rate <= b.angular_velocity);
    assert!(f.tilt_acceleration <= b.angular_acceleration);
    assert!(f.horizontal_share < 0.12, "{f:?}");
    assert!(f.yaw_acceleration <= 0.2 * f.tilt_acceleration, "{f:?}");
    assert!(f.yaw_rate <= f.horizontal_share * f.tilt_rate / b.heading_projection_min + 1e-12);
    // The aligned set's extents are J times the per-axis accelerations plus the gyroscopic box.
    let e = b.aligned_feedforward.axis_extents();
    let j = vehicle.inertia;
    assert!((e.z - (j.z * f.yaw_acceleration + f.gyroscopic.z)).abs() < 1e-12);
    assert!((e.x - (j.x * f.tilt_acceleration + f.gyroscopic.x)).abs() < 1e-12);
}

/// The paper's vehicle with slow, norm-saturated position gains (like the x500 preset's:
/// `M_p` = 0.5 m/s², `k_f` = 0.6, `k_s` = 1.7 1/s) on the paper's helix, certified with `form`.
fn slow_gains_on_the_helix(form: Lemma1Form) -> crate::Certificate<f64> {
    let mut gains = Gains::<f64>::paper();
    gains.position.saturation = 0.5;
    gains.position.saturation_shape = crate::PositionSaturation::Norm;
    gains.position.kf = 0.6;
    gains.position.ks = 1.7;
    gains.lemma1 = form;
    let helix = ReferenceTrajectory::<f64>::paper_helix().constants();
    certify(
        &Vehicle::paper(),
        &Limits::paper(),
        &gains,
        &helix,
        FilterStart::Zero,
    )
    .unwrap()
}

/// Given slow, norm-saturated position gains (like the x500 preset's) on the paper's helix, when `certify` runs, then the certified
/// torque set takes the norms of `ω_d`, `ω̇_d` from the desired frame's components where they
/// are tighter than Lemma 1's chain (here `|ω̇_d|`: the chain's bound adds the heading's terms
/// on the norm), while Theorem 2's conditions keep Lemma 1's norms.
#[test]
fn the_torque_set_takes_the_tighter_norms() {
    let vehicle = Vehicle::<f64>::paper();
    let c = slow_gains_on_the_helix(Lemma1Form::Tangential);
    let (b, f) = (&c.bounds, &c.bounds.desired_frame);
    let hypot = |x: f64, y: f64| (x * x + y * y).sqrt();
    let acceleration = hypot(f.tilt_acceleration, f.yaw_acceleration);
    assert!(
        acceleration < 0.8 * b.angular_acceleration,
        "{f:?} {}",
        b.angular_acceleration
    );
    assert_eq!(b.torque_set.angular_acceleration, acceleration);
    let rate = hypot(f.tilt_rate, f.yaw_rate).min(b.angular_velocity);
    let j = vehicle.inertia;
    assert!((b.torque_set.gyroscopic.z - 0.5 * (j.x - j.y).abs() * rate * rate).abs() < 1e-15);
    // Theorem 2's roll condition: J_11 U_ω̇d + ½|J_22 − J_33| U_ωd² + ι with Lemma 1's norms.
    let w2 = b.angular_velocity * b.angular_velocity;
    let theorem2 = j.x * b.angular_acceleration + 0.5 * (j.y - j.z).abs() * w2;
    assert!((b.torque_max.x - b.feedback_torque_axes.x - theorem2).abs() < 1e-12);
}

/// Given the set-up above (slow, norm-saturated gains on the paper's helix), when `certify` runs
/// with the desired frame's form of Lemma 1 instead of the tangential one, then the chain is the
/// same (same `U_ωd`, `U_ω̇d`, same torque set), Theorem 2's per-axis bound on each axis is the
/// certified set's extent there, below the tangential form's on every axis, and the yaw
/// condition names the desired frame's norms.
#[test]
fn the_desired_frame_form_judges_theorem2_on_the_sets_norms() {
    let vehicle = Vehicle::<f64>::paper();
    let tangential = slow_gains_on_the_helix(Lemma1Form::Tangential);
    let desired_frame = slow_gains_on_the_helix(Lemma1Form::DesiredFrame);
    let (t, d) = (&tangential.bounds, &desired_frame.bounds);
    assert_eq!(t.angular_velocity, d.angular_velocity);
    assert_eq!(t.angular_acceleration, d.angular_acceleration);
    assert_eq!(t.torque_set, d.torque_set);
    let extents = d.torque_set.axis_extents();
    for i in 0..3 {
        assert!(
            (d.torque_max[i] - extents[i]).abs() <= 1e-12 * extents[i],
            "axis {i}: {} vs the set's {}",
            d.torque_max[i],
            extents[i]
        );
        assert!(d.torque_max[i] < t.torque_max[i], "axis {i}");
    }
    // The tighter norms of the set: |ω̇_d| from the components, not the chain's.
    let f = &d.desired_frame;
    let acceleration = (f.tilt_acceleration.powi(2) + f.yaw_acceleration.powi(2)).sqrt();
    let feedforward_yaw = d.torque_max.z - d.feedback_torque_axes.z;
    let j = vehicle.inertia;
    let rate = (f.tilt_rate.powi(2) + f.yaw_rate.powi(2))
        .sqrt()
        .min(d.angular_velocity);
    let expected = j.z * acceleration + 0.5 * (j.x - j.y).abs() * rate * rate;
    assert!((feedforward_yaw - expected).abs() < 1e-12);
    let yaw = desired_frame
        .conditions
        .iter()
        .find(|c| c.name == "theorem2.torque_max_yaw")
        .unwrap();
    assert!(yaw.statement.contains("desired frame's norms"));
    assert_eq!(yaw.rhs, d.torque_max.z);
}
