//! The feedforward scale in closed loop (extension, docs/integral-action.md, "Feedforward
//! scale"): a vehicle whose attitude follows `R_d` ideally flies the paper's helix with a plant
//! heavier than modelled. The integral action alone holds the weight but leaves a periodic
//! residual (the mass error scales `p̈_d` too); with the feedforward scale the residual goes and
//! `μ` settles at the mass error.

use controller_core::{
    Controller, FeedforwardScaleGains, Gains, HeadingProfile, IntegralGains, ObserverGains,
    ReferenceTrajectory, Trajectory, Vehicle, VehicleState,
};
use nalgebra::{Rotation3, UnitQuaternion, Vector3};

const DT: f64 = 0.01;

fn helix() -> ReferenceTrajectory<f64> {
    let f = 2.0 * core::f64::consts::PI / 15.0;
    ReferenceTrajectory::Helix {
        center: Vector3::new(-3.0, 1.0, 4.5),
        radius: 1.0,
        vertical_amplitude: 1.0,
        frequency: f,
        heading: HeadingProfile::Sinusoidal {
            amplitude: core::f64::consts::PI,
            frequency: f,
            offset: 0.0,
        },
    }
}

fn gains(scale: Option<FeedforwardScaleGains<f64>>) -> Gains<f64> {
    let mut g = Gains::paper();
    g.integral = Some(IntegralGains {
        gain: 5.0,
        level: Vector3::new(0.5, 0.5, 2.2),
        rate: Vector3::new(2.0, 2.0, 10.0),
        bandwidth: 1.0,
        observer: Some(ObserverGains {
            velocity_gain: 6.0,
            disturbance_gain: 9.0,
            error_limit: 0.05,
        }),
        feedforward_scale: scale,
    });
    g
}

fn scale() -> FeedforwardScaleGains<f64> {
    FeedforwardScaleGains {
        gain: 4.0,
        excitation: 0.1,
        level: 0.25,
        rate: 0.05,
        tracking_limit: 0.05,
    }
}

/// Flies the helix from its start for `seconds` with a plant `1 + mass_error` times heavier;
/// returns the largest `|p − p_d|` \[m\] over the last 15 s and the controller.
fn fly(gains: Gains<f64>, mass_error: f64, seconds: f64) -> (f64, Controller<f64>) {
    let vehicle = Vehicle::paper();
    let reference = helix();
    let mut c = Controller::new(vehicle, gains, &reference.constants()).unwrap();
    let start = reference.sample(0.0);
    let mut state = VehicleState {
        position: start.position,
        velocity: start.velocity,
        attitude: UnitQuaternion::identity(),
        angular_velocity: Vector3::zeros(),
    };
    let m_true = vehicle.mass * (1.0 + mass_error);
    let steps = (seconds / DT).round() as usize;
    let mut worst: f64 = 0.0;
    for k in 0..steps {
        let r = reference.sample(k as f64 * DT);
        if k as f64 * DT >= seconds - 15.0 {
            worst = worst.max((state.position - r.position).norm());
        }
        let out = c.step(&state, &r, DT).unwrap();
        let d = out.diagnostics;
        assert!(
            d.feedforward_scale.abs()
                <= gains
                    .integral
                    .unwrap()
                    .feedforward_scale
                    .map_or(0.0, |f| f.level)
        );
        let accel = d.thrust_direction * (out.thrust / m_true) - Vector3::z() * vehicle.gravity;
        state.position += state.velocity * DT + accel * (0.5 * DT * DT);
        state.velocity += accel * DT;
        state.attitude = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(
            d.desired_rotation,
        ));
    }
    (worst, c)
}

#[test]
fn feedforward_scale_removes_the_periodic_residual_of_a_mass_error() {
    let e = 0.2;
    let (without, _) = fly(gains(None), e, 90.0);
    let (with, c) = fly(gains(Some(scale())), e, 90.0);
    println!("largest error over the last 15 s: without {without} m, with {with} m");
    // Without: the weight is held but p̈_d is short by E/(1 + E) of itself, a turning error.
    assert!(without > 3e-3, "{without}");
    assert!(with < 0.1 * without, "{with} vs {without}");
    // μ settles at the mass error, and η no longer carries the turning part.
    let mu = c.feedforward_scale_state().filtered;
    assert!((mu - e).abs() < 0.02, "mu = {mu}");
}

#[test]
fn nominal_plant_keeps_the_scale_near_zero() {
    let (with, c) = fly(gains(Some(scale())), 0.0, 60.0);
    let mu = c.feedforward_scale_state().filtered;
    assert!(mu.abs() < 0.01, "mu = {mu}");
    assert!(with < 1e-3, "{with}");
}

#[test]
fn freeze_holds_and_reset_zeroes_the_scale() {
    let (_, mut c) = fly(gains(Some(scale())), 0.2, 30.0);
    let held = c.feedforward_scale_state();
    assert!(held.estimate > 0.02, "{held:?}");
    c.set_integral_frozen(true);
    let reference = helix();
    let state = VehicleState {
        position: reference.sample(30.0).position + Vector3::new(0.3, 0.0, 0.0),
        velocity: Vector3::zeros(),
        attitude: UnitQuaternion::identity(),
        angular_velocity: Vector3::zeros(),
    };
    for k in 0..50 {
        c.step(&state, &reference.sample(30.0 + k as f64 * DT), DT)
            .unwrap();
        assert_eq!(c.feedforward_scale_state().estimate, held.estimate);
    }
    c.reset_integral();
    assert_eq!(c.feedforward_scale_state().estimate, 0.0);
    assert_eq!(c.feedforward_scale_state().filtered, 0.0);
}
