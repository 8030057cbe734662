use super::*;

fn cfg() -> EstimatorConfig {
    EstimatorConfig {
        latency_us: 10_000,
        calibration_samples: 100,
        position_sigma: 1e-3,
        accel_psd: 2.0,
        gravity: 9.81,
    }
}

/// The bias is the mean of the still samples; motion restarts the calibration.
#[test]
fn gyro_calibration() {
    let mut e = Estimator::new(cfg());
    let g = Vector3::new(0.0, 0.0, 9.81);
    let b = Vector3::new(0.01, -0.02, 0.005);
    for i in 0..50 {
        e.on_imu(&b, &g, i * 1000);
    }
    e.on_imu(&Vector3::new(1.0, 0.0, 0.0), &g, 50_000); // moved
    for i in 0..99 {
        e.on_imu(&b, &g, 51_000 + i * 1000);
    }
    assert!(e.calibrating());
    e.on_imu(&b, &g, 200_000);
    assert!(!e.calibrating());
    assert!((e.gyro_bias() - b).norm() < 1e-7);
    e.on_imu(&(b + Vector3::new(0.3, 0.0, 0.0)), &g, 201_000);
    assert!((e.angular_velocity() - Vector3::new(0.3, 0.0, 0.0)).norm() < 1e-6);
}

/// A ramp p = 2 t m measured at 200 Hz with the known latency: the velocity converges
/// to 2 m/s and the extrapolated position to the true position at "now".
#[test]
fn velocity_from_positions_with_latency() {
    let mut e = Estimator::new(cfg());
    let q = Quaternion::identity();
    for k in 1..400u64 {
        let t_meas = k * 5_000;
        let p = Vector3::new(2.0 * t_meas as f32 * 1e-6, 0.0, 1.0);
        assert_eq!(e.on_pose(&p, &q, t_meas + 10_000), PoseCheck::Used);
    }
    let now = 399 * 5_000 + 10_000 + 3_000;
    let s = e.estimate(now).unwrap();
    assert!((s.velocity.x - 2.0).abs() < 1e-2, "{}", s.velocity);
    let truth = 2.0 * now as f32 * 1e-6;
    assert!(
        (s.position.x - truth).abs() < 1e-3,
        "{} vs {truth}",
        s.position.x
    );
}

/// The latency correction: a pose measured 10 ms ago while the body turned at 1 rad/s
/// about z gives today's attitude (yaw advanced by ~10 mrad).
#[test]
fn attitude_latency_is_propagated() {
    let mut c = cfg();
    c.calibration_samples = 1;
    let mut e = Estimator::new(c);
    let g = Vector3::new(0.0, 0.0, 9.81);
    e.on_imu(&Vector3::zeros(), &g, 0); // calibrated with zero bias
    for k in 1..=30u64 {
        e.on_imu(&Vector3::new(0.0, 0.0, 1.0), &g, k * 1000);
    }
    // Measured at t = 20 ms (yaw 0.02 rad then, if yaw started at 0 at t = 0), arrives at 30.
    let q_meas = UnitQuaternion::from_euler_angles(0.0f32, 0.0, 0.02);
    e.on_pose(&Vector3::zeros(), q_meas.quaternion(), 30_000);
    let (_, _, yaw) = e.estimate(30_000).unwrap().attitude.euler_angles();
    assert!((yaw - 0.03).abs() < 2e-4, "{yaw}");
}

/// The samples taken before the first pose (no attitude, so no inertial acceleration) share
/// the history with the later ones but stay out of the acceleration mean: over a window
/// holding 10 such samples and 5 later ones at 2 m/s² up, the mean is 2 m/s² (it would be
/// 2/3 if the early ones counted as zeros).
#[test]
fn samples_before_the_first_pose_stay_out_of_the_acceleration_mean() {
    let mut c = cfg();
    c.calibration_samples = 1;
    let mut e = Estimator::new(c);
    let still = Vector3::new(0.0, 0.0, 9.81);
    for k in 1..=30u64 {
        e.on_imu(&Vector3::zeros(), &still, k * 1000);
    }
    // Measured at 20 ms (latency 10 ms), level: the window (20, 35] ms starts here.
    let q = Quaternion::identity();
    assert_eq!(e.on_pose(&Vector3::zeros(), &q, 30_000), PoseCheck::Used);
    for k in 31..=35u64 {
        e.on_imu(&Vector3::zeros(), &Vector3::new(0.0, 0.0, 11.81), k * 1000);
    }
    let s = e.estimate(35_000).unwrap();
    // v = 0 + ā dt over dt = 15 ms.
    assert!(
        (s.velocity.z - 2.0 * 0.015).abs() < 1e-6,
        "{}",
        s.velocity.z
    );
}

/// Non-finite poses and bad quaternions are refused and flagged.
#[test]
fn refuses_bad_poses() {
    let mut e = Estimator::new(cfg());
    let q = Quaternion::identity();
    assert_eq!(
        e.on_pose(&Vector3::new(f32::NAN, 0.0, 0.0), &q, 20_000),
        PoseCheck::NonFinite
    );
    assert!(e.last_pose_bad());
    assert_eq!(
        e.on_pose(&Vector3::zeros(), &(q * 2.0), 20_000),
        PoseCheck::BadQuaternion
    );
    assert_eq!(e.on_pose(&Vector3::zeros(), &q, 20_000), PoseCheck::Used);
    assert!(!e.last_pose_bad());
    assert_eq!(
        e.on_pose(&Vector3::zeros(), &q, 19_000),
        PoseCheck::OutOfOrder
    );
    assert!(e.estimate(20_000).is_some());
    assert!(!e.on_imu(&Vector3::new(f32::INFINITY, 0.0, 0.0), &Vector3::z(), 1));
}
