//! The integral action in closed loop (extension, docs/integral-action.md): a vehicle whose
//! attitude follows `R_d` ideally, with a plant mass error and a constant force, flown by the
//! full controller.

use controller_core::{
    Controller, Gains, IntegralGains, IntegralState, ObserverGains, ReferenceSample,
    TrajectoryConstants, Vehicle, VehicleState,
};
use nalgebra::{Rotation3, UnitQuaternion, Vector3};

const DT: f64 = 0.01;

fn integral_gains() -> IntegralGains<f64> {
    IntegralGains {
        feedforward_scale: None,
        gain: 2.0,
        level: Vector3::new(0.5, 0.5, 1.5),
        rate: Vector3::new(0.5, 0.5, 1.0),
        bandwidth: 5.0,
        observer: None,
    }
}

/// Plant: `p̈ = (T / m_true) ρ − g e₃ + d` with the attitude equal to the last `R_d` (so
/// `ρ = R_d e₃`), propagated exactly over each sample (constant acceleration).
/// Returns the final position error \[m\] and the controller.
fn fly(
    gains: Gains<f64>,
    mass_error: f64,
    force: Vector3<f64>,
    seconds: f64,
) -> (Vector3<f64>, Controller<f64>) {
    fly_from(
        Vector3::new(0.5, -0.3, 0.2),
        gains,
        mass_error,
        force,
        seconds,
        |_| {},
    )
}

/// [`fly`] from `start` \[m\], calling `each` with the controller after every sample.
fn fly_from(
    start: Vector3<f64>,
    gains: Gains<f64>,
    mass_error: f64,
    force: Vector3<f64>,
    seconds: f64,
    mut each: impl FnMut(&Controller<f64>),
) -> (Vector3<f64>, Controller<f64>) {
    let vehicle = Vehicle::paper();
    let mut c = Controller::new(vehicle, gains, &TrajectoryConstants::zero()).unwrap();
    let reference = ReferenceSample::hold(Vector3::zeros(), 0.3);
    let mut state = VehicleState {
        position: start,
        velocity: Vector3::zeros(),
        attitude: UnitQuaternion::identity(),
        angular_velocity: Vector3::zeros(),
    };
    let m_true = vehicle.mass * (1.0 + mass_error);
    for _ in 0..(seconds / DT).round() as usize {
        let out = c.step(&state, &reference, DT).unwrap();
        let d = out.diagnostics;
        let accel =
            d.thrust_direction * (out.thrust / m_true) - Vector3::z() * vehicle.gravity + force;
        state.position += state.velocity * DT + accel * (0.5 * DT * DT);
        state.velocity += accel * DT;
        state.attitude = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(
            d.desired_rotation,
        ));
        // The integral's applied value stays in its box at every sample.
        if let Some(i) = &gains.integral {
            for k in 0..3 {
                assert!(d.integral[k].abs() <= i.level[k]);
            }
        }
        each(&c);
    }
    (state.position - reference.position, c)
}

/// The paper's law's steady error under a mass error `e` and force `d`, from its equilibrium
/// (filters at rest, `u_f = u_s = ubar_p`, `ṽ = 0`): `u_f = e g e₃ − (1 + e) d`,
/// `k_p z₁ + k_v c u_f = −M_p atanh(u_f / M_p)`, `p̃ = z₁ − u_f / (k_f k_s)`.
fn paper_steady_error(e: f64, d: Vector3<f64>) -> Vector3<f64> {
    let g = Gains::<f64>::paper().position;
    let c = 1.0 / g.kf + 1.0 / g.ks;
    let u_f = Vector3::z() * (e * 9.81) - d * (1.0 + e);
    u_f.map(|u| {
        let z1 = (-g.saturation * (u / g.saturation).atanh() - g.kv * c * u) / g.kp;
        z1 - u / (g.kf * g.ks)
    })
}

#[test]
fn integral_action_removes_the_steady_error_the_paper_law_keeps() {
    let force = Vector3::new(0.3, -0.2, 0.0);
    let e = 0.1;
    let (without, _) = fly(Gains::paper(), e, force, 40.0);
    let expected = paper_steady_error(e, force);
    // Without: it settles where the paper's equilibrium says (about 0.5 m low).
    assert!(expected.z < -0.4, "{expected}");
    assert!(
        (without - expected).amax() < 1e-3,
        "{without} vs {expected}"
    );

    let mut gains = Gains::paper();
    gains.integral = Some(integral_gains());
    let (with, c) = fly(gains, e, force, 40.0);
    assert!(with.amax() < 1e-4, "{with}");
    // Equilibrium: η_f = −d_eff, here u_f + η_f = e g e₃ − (1 + e) d with u_f → 0.
    let eta_f = c.integral_state().filtered;
    let d_eff = Vector3::z() * (e * 9.81) - force * (1.0 + e);
    assert!((eta_f - d_eff).amax() < 1e-4, "{eta_f} vs {d_eff}");
}

fn observer() -> ObserverGains<f64> {
    ObserverGains {
        velocity_gain: 4.0,
        disturbance_gain: 4.0,
        error_limit: 0.05,
    }
}

/// With the disturbance observer anchoring the estimate, the same mass error and force leave no
/// steady error either, and the estimate settles at the same `−d_eff`.
#[test]
fn the_observer_removes_the_steady_error_too() {
    let force = Vector3::new(0.3, -0.2, 0.0);
    let e = 0.1;
    let mut gains = Gains::paper();
    gains.integral = Some(IntegralGains {
        observer: Some(observer()),
        ..integral_gains()
    });
    let (with, c) = fly(gains, e, force, 40.0);
    assert!(with.amax() < 1e-4, "{with}");
    let eta_f = c.integral_state().filtered;
    let d_eff = Vector3::z() * (e * 9.81) - force * (1.0 + e);
    assert!((eta_f - d_eff).amax() < 1e-4, "{eta_f} vs {d_eff}");
}

/// Given an exact model (no disturbance at all) and a start 8 m away, which saturates the
/// position feedback for seconds, when the integral of z₁ alone runs, then its estimate winds
/// up to its level; when the observer anchors it, then it stays below a quarter of
/// the level: the clamped z₁ term drifts it at most at k_i z̄, which the innovation term balances
/// at |η| ≈ k_i z̄ L_v / L_d = 0.1 m/s² (docs/integral-action.md; 0.118 at the worst sample).
#[test]
fn the_observer_keeps_a_transient_from_winding_the_estimate_up() {
    let start = Vector3::new(8.0, -6.0, 4.0);
    let worst = |observer: Option<ObserverGains<f64>>| {
        let ig = IntegralGains {
            observer,
            ..integral_gains()
        };
        let mut gains = Gains::paper();
        gains.integral = Some(ig);
        let mut worst = Vector3::<f64>::zeros();
        fly_from(start, gains, 0.0, Vector3::zeros(), 20.0, |c| {
            worst = worst.sup(&c.integral_state().estimate.abs());
        });
        println!("{observer:?}: worst |eta| {:?}", worst.as_slice());
        worst.component_div(&ig.level).amax()
    };
    let alone = worst(None);
    let anchored = worst(Some(observer()));
    assert!(alone > 0.99, "integral of z1 alone: {alone}");
    assert!(anchored < 0.25, "with the observer: {anchored}");
}

#[test]
fn freeze_holds_and_reset_zeroes_the_estimate() {
    let mut gains = Gains::paper();
    gains.integral = Some(integral_gains());
    let (_, mut c) = fly(gains, 0.1, Vector3::zeros(), 10.0);
    let held = c.integral_state().estimate;
    assert!(held.z > 0.5);
    c.set_integral_frozen(true);
    let reference = ReferenceSample::hold(Vector3::new(3.0, 0.0, 0.0), 0.0);
    let state = VehicleState {
        position: Vector3::zeros(),
        velocity: Vector3::zeros(),
        attitude: UnitQuaternion::identity(),
        angular_velocity: Vector3::zeros(),
    };
    for _ in 0..50 {
        let out = c.step(&state, &reference, DT).unwrap();
        assert_eq!(c.integral_state().estimate, held);
        // Frozen, the estimate is still applied (through η_f).
        assert!(out.diagnostics.integral.z > 0.0);
    }
    c.reset_integral();
    assert_eq!(c.integral_state(), IntegralState::zero());
}

#[test]
fn refused_step_leaves_the_estimate_untouched() {
    let mut gains = Gains::paper();
    gains.integral = Some(integral_gains());
    let (_, mut c) = fly(gains, 0.1, Vector3::zeros(), 2.0);
    let before = c.integral_state();
    let mut state = VehicleState {
        position: Vector3::new(f64::NAN, 0.0, 0.0),
        velocity: Vector3::zeros(),
        attitude: UnitQuaternion::identity(),
        angular_velocity: Vector3::zeros(),
    };
    let reference = ReferenceSample::hold(Vector3::zeros(), 0.0);
    assert!(c.step(&state, &reference, DT).is_err());
    state.position = Vector3::zeros();
    assert!(c.step(&state, &reference, f64::NAN).is_err());
    assert_eq!(c.integral_state(), before);
}

#[test]
fn controller_refuses_levels_that_let_the_thrust_vanish() {
    let mut gains = Gains::paper();
    let mut i = integral_gains();
    i.level.z = 8.0;
    gains.integral = Some(i);
    let e = Controller::new(Vehicle::paper(), gains, &TrajectoryConstants::zero()).unwrap_err();
    assert!(e.to_string().contains("M_p + M_i_z"), "{e}");
    i.level.z = f64::INFINITY;
    gains.integral = Some(i);
    let e = Controller::new(Vehicle::paper(), gains, &TrajectoryConstants::zero()).unwrap_err();
    assert!(e.to_string().contains("M_i_z"), "{e}");
}

mod off_path {
    use super::*;
    use proptest::prelude::*;

    fn v3(r: f64) -> impl Strategy<Value = Vector3<f64>> {
        (-r..r, -r..r, -r..r).prop_map(|(a, b, c)| Vector3::new(a, b, c))
    }

    proptest! {
        /// With the integral off, `u` is the paper's sum from the position law itself, bit for
        /// bit, and the applied η_f is zero, along random sequences of states.
        #[test]
        fn off_is_the_papers_law(ps in proptest::collection::vec((v3(5.0), v3(3.0)), 1..30)) {
            let gains = Gains::<f64>::paper();
            let mut c = Controller::new(Vehicle::paper(), gains, &TrajectoryConstants::zero()).unwrap();
            let reference = ReferenceSample::hold(Vector3::new(0.1, 0.2, 0.3), 0.4);
            for (p, v) in ps {
                let filter = c.filter_state();
                let state = VehicleState {
                    position: p,
                    velocity: v,
                    attitude: UnitQuaternion::identity(),
                    angular_velocity: Vector3::zeros(),
                };
                let out = c.step(&state, &reference, DT).unwrap();
                let zero = Vector3::zeros();
                let law = gains.position.evaluate(
                    None, &(p - reference.position), &(v - reference.velocity), &filter,
                    &zero, &zero, &zero, 9.81,
                );
                prop_assert_eq!(out.diagnostics.u, law.u);
                prop_assert_eq!(out.diagnostics.integral, zero);
                prop_assert_eq!(c.integral_state(), IntegralState::zero());
            }
        }
    }
}

/// The no-dive floor must stay below `m(g − M_p − M_i,z)` with the integral on (the vertical
/// part of u can drop by that much), and below `m(g − M_p)` without it.
#[test]
fn thrust_floor_accounts_for_the_integral_level() {
    use controller_core::ThrustMode;
    let v = Vehicle::<f64>::paper();
    // Between the two limits: 0.46 (9.81 − 2 − 1.5) = 2.9026 < 3.0 < 0.46 (9.81 − 2) = 3.5926.
    let floor = ThrustMode::BodyAxisProjection { floor: 3.0 };
    let mut off = Controller::new(v, Gains::paper(), &TrajectoryConstants::zero()).unwrap();
    assert!(off.set_thrust_mode(floor).is_ok());
    let mut gains = Gains::paper();
    gains.integral = Some(integral_gains());
    let mut on = Controller::new(v, gains, &TrajectoryConstants::zero()).unwrap();
    let e = on.set_thrust_mode(floor).unwrap_err();
    assert!(e.to_string().contains("thrust_floor"), "{e}");
    assert!(on
        .set_thrust_mode(ThrustMode::BodyAxisProjection { floor: 2.8 })
        .is_ok());
}
