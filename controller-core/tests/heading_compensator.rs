//! The compensated heading in closed loop (extension, controller-core's `heading_compensator`):
//! a vehicle whose attitude follows `R_d` ideally, started off the reference so that the thrust
//! direction tilts across the heading and turns, flown by the full controller with and without
//! the compensator.

use controller_core::{
    certify, Controller, FilterStart, Gains, HeadingCompensatorGains, Limits, ReferenceSample,
    TrajectoryConstants, Vehicle, VehicleState,
};
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};

const DT: f64 = 0.01;
const HEADING: f64 = 0.7;

fn compensator() -> HeadingCompensatorGains<f64> {
    HeadingCompensatorGains {
        level: 0.3,
        gain: 1.0,
    }
}

/// What one sample showed: the desired frame's `ω_d`, `ω̇_d` (desired body frame) and `R_d`.
struct Sample {
    angular_velocity: Vector3<f64>,
    angular_acceleration: Vector3<f64>,
    rotation: Matrix3<f64>,
}

/// The paper's vehicle and gains, `heading_compensator` as given, from `start` \[m\] off a hold
/// at the origin with heading [`HEADING`], the attitude following `R_d` exactly; every sample.
fn fly(
    heading_compensator: Option<HeadingCompensatorGains<f64>>,
    start: Vector3<f64>,
    seconds: f64,
) -> Vec<Sample> {
    let vehicle = Vehicle::paper();
    let gains = Gains {
        heading_compensator,
        ..Gains::paper()
    };
    let mut c = Controller::new(vehicle, gains, &TrajectoryConstants::zero()).unwrap();
    let reference = ReferenceSample::hold(Vector3::zeros(), HEADING);
    let mut state = VehicleState {
        position: start,
        velocity: Vector3::zeros(),
        attitude: UnitQuaternion::from_euler_angles(0.0, 0.0, HEADING),
        angular_velocity: Vector3::zeros(),
    };
    let mut samples = Vec::new();
    for _ in 0..(seconds / DT).round() as usize {
        let out = c.step(&state, &reference, DT).unwrap();
        let d = out.diagnostics;
        let accel =
            d.thrust_direction * (out.thrust / vehicle.mass) - Vector3::z() * vehicle.gravity;
        state.position += state.velocity * DT + accel * (0.5 * DT * DT);
        state.velocity += accel * DT;
        state.attitude = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(
            d.desired_rotation,
        ));
        samples.push(Sample {
            angular_velocity: d.desired_angular_velocity,
            angular_acceleration: d.desired_angular_acceleration,
            rotation: d.desired_rotation,
        });
    }
    samples
}

/// The heading of `R_d`: the angle of its body x axis in the horizontal plane \[rad\].
fn heading_of(rotation: &Matrix3<f64>) -> f64 {
    rotation[(1, 0)].atan2(rotation[(0, 0)])
}

fn largest(samples: &[Sample], f: impl Fn(&Sample) -> f64) -> f64 {
    samples.iter().map(f).fold(0.0, f64::max)
}

/// Given an offset across the heading, when flown with the compensator, then every sample's
/// `ω_d`, `ω̇_d` stay within the compensated certificate's bounds (norms and desired-frame yaw
/// components), the frame yaws far less than the paper's frame does on the same flight, and the
/// heading settles on `ψ_d` once the vehicle is back on the reference.
#[test]
fn the_compensated_frame_stays_within_its_certificate_and_settles_on_the_heading() {
    let start = Vector3::new(4.0, -3.0, 1.0);
    let with = fly(Some(compensator()), start, 20.0);
    let without = fly(None, start, 20.0);

    let gains = Gains {
        heading_compensator: Some(compensator()),
        ..Gains::paper()
    };
    let cert = certify(
        &Vehicle::paper(),
        &Limits::paper(),
        &gains,
        &TrajectoryConstants::zero(),
        FilterStart::Zero,
    )
    .unwrap();
    let b = &cert.bounds;
    let slack = 1.0 + 1e-9;
    for (i, s) in with.iter().enumerate() {
        assert!(
            s.angular_velocity.norm() <= b.angular_velocity * slack,
            "sample {i}: |ω_d| {} > {}",
            s.angular_velocity.norm(),
            b.angular_velocity
        );
        assert!(
            s.angular_acceleration.norm() <= b.angular_acceleration * slack,
            "sample {i}: |ω̇_d| {} > {}",
            s.angular_acceleration.norm(),
            b.angular_acceleration
        );
        assert!(
            s.angular_velocity.z.abs() <= b.desired_frame.yaw_rate * slack,
            "sample {i}"
        );
        assert!(
            s.angular_acceleration.z.abs() <= b.desired_frame.yaw_acceleration * slack,
            "sample {i}"
        );
    }

    // The paper's frame yaws with the tilt across the heading; the compensated one only as its
    // bounded correction asks (here it starts on ψ_d, so only to undo the tilt's drift).
    let yaw_rate = |s: &Sample| s.angular_velocity.z.abs();
    let yaw_acceleration = |s: &Sample| s.angular_acceleration.z.abs();
    let (paper_rate, compensated_rate) = (largest(&without, yaw_rate), largest(&with, yaw_rate));
    let (paper_acc, compensated_acc) = (
        largest(&without, yaw_acceleration),
        largest(&with, yaw_acceleration),
    );
    assert!(
        paper_rate > 0.05,
        "the flight must tilt across the heading: {paper_rate}"
    );
    assert!(
        compensated_acc < 0.5 * paper_acc,
        "|ω̇_d,3| {compensated_acc} vs the paper's frame's {paper_acc}"
    );
    assert!(
        compensated_rate < paper_rate,
        "|ω_d,3| {compensated_rate} vs {paper_rate}"
    );

    // Back on the reference, R_d's heading is ψ_d (the compensator's error decays at least as
    // exp(−κ t), κ = L tanh(k_ψ / L), once the thrust direction stops turning).
    let end = with.last().unwrap();
    let error = (heading_of(&end.rotation) - HEADING).sin().abs();
    assert!(error < 1e-3, "heading error at the end {error}");
    // Without the compensator the heading is ψ_d at every sample where ρ is vertical; at the
    // end both frames agree.
    let paper_end = without.last().unwrap();
    assert!((heading_of(&paper_end.rotation) - HEADING).sin().abs() < 1e-6);
}

/// Given the compensator's gains, when one is not positive, then the controller refuses them by
/// name.
#[test]
fn bad_compensator_gains_are_refused_by_name() {
    for (level, gain, name) in [
        (0.0, 1.0, "L_psi"),
        (0.3, -1.0, "k_psi"),
        (f64::NAN, 1.0, "L_psi"),
    ] {
        let gains = Gains {
            heading_compensator: Some(HeadingCompensatorGains { level, gain }),
            ..Gains::paper()
        };
        let e = Controller::new(Vehicle::paper(), gains, &TrajectoryConstants::zero()).unwrap_err();
        assert!(format!("{e}").contains(name), "{e}");
    }
}
