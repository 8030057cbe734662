//! Tests of the reference trajectories against their closed-form derivatives and Assumption 1's
//! constants.

use super::*;
use approx::assert_relative_eq;

fn trajectories() -> [ReferenceTrajectory<f64>; 3] {
    [
        ReferenceTrajectory::Hover {
            point: Vector3::new(1.0, 2.0, 3.0),
            heading: HeadingProfile::Constant { yaw: 0.4 },
        },
        ReferenceTrajectory::paper_helix(),
        ReferenceTrajectory::FigureEight {
            center: Vector3::new(0.0, 0.0, 2.0),
            x_amplitude: 2.0,
            y_amplitude: 1.5,
            frequency: 0.5,
            heading: HeadingProfile::Sinusoidal {
                amplitude: 0.8,
                frequency: 0.3,
                offset: 0.1,
            },
        },
    ]
}

/// Each derivative agrees with a central difference of the one below it.
#[test]
fn derivatives_match_finite_differences() {
    let h = 1e-5;
    for traj in trajectories() {
        for k in 0..50 {
            let t = 0.37 * k as f64;
            let (a, b, c) = (traj.sample(t - h), traj.sample(t), traj.sample(t + h));
            let fd3 = |f: fn(&ReferenceSample<f64>) -> Vector3<f64>| (f(&c) - f(&a)) / (2.0 * h);
            let fd2 = |f: fn(&ReferenceSample<f64>) -> Vector2<f64>| (f(&c) - f(&a)) / (2.0 * h);
            assert_relative_eq!(fd3(|s| s.position), b.velocity, epsilon = 1e-6);
            assert_relative_eq!(fd3(|s| s.velocity), b.acceleration, epsilon = 1e-6);
            assert_relative_eq!(fd3(|s| s.acceleration), b.jerk, epsilon = 1e-6);
            assert_relative_eq!(fd3(|s| s.jerk), b.snap, epsilon = 1e-6);
            assert_relative_eq!(fd2(|s| s.heading), b.heading_rate, epsilon = 1e-6);
            assert_relative_eq!(
                fd2(|s| s.heading_rate),
                b.heading_acceleration,
                epsilon = 1e-6
            );
            assert_relative_eq!(b.heading.norm(), 1.0, epsilon = 1e-12);
        }
    }
}

/// The constants bound every sample, and for the helix and the heading sinusoid they are
/// the exact maxima (a dense sampling gets within 0.1 % of them).
#[test]
fn constants_bound_samples_and_are_tight_where_exact() {
    for traj in trajectories() {
        let k = traj.constants();
        let mut max = TrajectoryConstants::<f64>::zero();
        for i in 0..200_000 {
            let s = traj.sample(i as f64 * 1e-3);
            assert!(k.contain(&s, 1e-12), "{traj:?} at {i}");
            let a = s.acceleration;
            max.horizontal_acceleration = max.horizontal_acceleration.max(a.xy().norm());
            max.vertical_acceleration = max.vertical_acceleration.max(a.z.abs());
            max.jerk = max.jerk.max(s.jerk.norm());
            max.snap = max.snap.max(s.snap.norm());
            max.heading_rate = max.heading_rate.max(s.heading_rate.norm());
            max.heading_acceleration = max.heading_acceleration.max(s.heading_acceleration.norm());
        }
        if matches!(traj, ReferenceTrajectory::Helix { .. }) {
            for (m, e) in [
                (max.horizontal_acceleration, k.horizontal_acceleration),
                (max.vertical_acceleration, k.vertical_acceleration),
                (max.jerk, k.jerk),
                (max.snap, k.snap),
                (max.heading_rate, k.heading_rate),
                (max.heading_acceleration, k.heading_acceleration),
            ] {
                assert!(m > 0.999 * e, "sampled max {m} vs closed form {e}");
            }
        }
    }
}

#[test]
fn paper_helix_values() {
    let f = 2.0 * core::f64::consts::PI / 15.0;
    let s = ReferenceTrajectory::<f64>::paper_helix().sample(0.0);
    assert_relative_eq!(s.position, Vector3::new(-2.0, 1.0, 5.5), epsilon = 1e-12);
    assert_relative_eq!(s.velocity, Vector3::new(0.0, f, 0.0), epsilon = 1e-12);
    assert_relative_eq!(s.yaw(), 0.0, epsilon = 1e-12);
    let k = ReferenceTrajectory::<f64>::paper_helix().constants();
    assert_relative_eq!(k.heading_rate, core::f64::consts::PI * f, epsilon = 1e-12);
}
