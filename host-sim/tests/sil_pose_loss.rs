//! SIL scenario 2: pose lost in flight: failsafe within 100 ms of the pose timing out (one
//! 10 ms control tick after the 100 ms limit), level, descending, disarmed after 2 s.

use firmware::ground_station;
use host_sim::harness::sil::{run, scenarios};

#[test]
fn pose_loss_failsafe_level_descent_and_disarm() {
    for seed in [1, 5, 9] {
        let setup = scenarios::pose_loss(seed);
        let mut throttle_after_disarm = 0.0f32;
        let mut disarmed_at = None;
        let s = run(&setup, |r| {
            if r.state == "disarmed" && r.t_s > 6.0 {
                disarmed_at.get_or_insert(r.t_s);
                throttle_after_disarm = throttle_after_disarm.max(
                    r.throttle1
                        .max(r.throttle2)
                        .max(r.throttle3)
                        .max(r.throttle4),
                );
            }
        })
        .unwrap();
        let last = s.last_pose_s.expect("poses were delivered");
        let fs = s.failsafe_at_s.expect("failsafe entered");
        let age = fs - last;
        assert!(
            age > 0.100 && age <= 0.110 + 1e-9,
            "failsafe {age} s after the last pose"
        );
        // Level (after the first 0.5 s of the failsafe) and descending.
        let tilt = s.failsafe_max_tilt_rad.unwrap();
        assert!(tilt.to_degrees() < 10.0, "{}", tilt.to_degrees());
        let vz = s.failsafe_mean_vz_m_s.unwrap();
        assert!(vz < -0.3, "{vz}");
        // Disarmed 2 s after the last pose (one tick of resolution), motors stopped.
        let d = s.disarmed_at_s.unwrap();
        assert!(
            (d - last - 2.0).abs() <= 0.011,
            "disarmed {} s after the last pose",
            d - last
        );
        assert_eq!(s.final_state, "disarmed");
        assert_eq!(throttle_after_disarm, 0.0);
        assert_eq!(s.spun_while_disarmed, 0);
        assert_eq!(s.throttle_violations, 0);
    }
}

/// Takeoff, a hover target, landing and the automatic disarm on the ground.
#[test]
fn takeoff_hover_land_disarm() {
    let s = run(&scenarios::takeoff_land(3), |_| {}).unwrap();
    let events: Vec<&str> = s.events.iter().map(|(_, e)| e.as_str()).collect();
    assert!(
        events.iter().any(|e| e.contains("mode takeoff")),
        "{events:?}"
    );
    assert!(events.iter().any(|e| e.contains("mode hover")));
    assert!(events.iter().any(|e| e.contains("mode land")));
    assert!(
        events
            .iter()
            .any(|e| e.contains("armed -> disarmed (landed)")),
        "{events:?}"
    );
    assert_eq!(s.final_state, "disarmed");
    assert!(s.rms_position_error_last_10s_m < 0.05);
    assert_eq!(s.refused_commands, 0);
    assert_eq!(s.spun_while_disarmed, 0);
}

/// Pose lost close to the ground: the failsafe descends, the ground is detected (thrust below
/// weight while the accelerometer reads g and the dead-reckoned vertical speed is zero) and
/// the vehicle disarms before the 2 s limit.
#[test]
fn pose_loss_near_the_ground_disarms_on_the_ground() {
    let mut setup = scenarios::takeoff_land(4);
    setup.commands = vec![
        (0.0, ground_station::arm(false)),
        (0.2, ground_station::takeoff(0.4)),
    ];
    setup.pose_outage = Some((6.0, f64::INFINITY));
    setup.duration_s = 10.0;
    let s = run(&setup, |_| {}).unwrap();
    let last = s.last_pose_s.unwrap();
    let d = s.disarmed_at_s.unwrap();
    assert!(
        d - last < 1.95,
        "disarmed {} s after the last pose",
        d - last
    );
    assert!(
        s.events
            .iter()
            .any(|(_, e)| e.contains("on the ground in failsafe")),
        "{:#?}",
        s.events
    );
    assert_eq!(s.final_state, "disarmed");
}

/// Pose rates and latency: at 300 Hz with 25 ms latency (configured in the firmware) and at
/// 100 Hz with 5 % dropouts, the hover is held to centimetres and the estimate stays within
/// millimetres of the truth.
///
/// The hand launch releases the vehicle with its motors stopped (the x500's idle throttle is
/// 0): the spin-up, `1.5 τ_m` of missing thrust, sinks it at `1.5 τ_m g` ≈ 0.37 m/s, a sag of
/// about 0.7 m that the certified gains' output filter (`k_f` = 0.25/s: the slowest mode,
/// `e^{-k_f t}`) removes in `ln(0.7 / 0.002) / k_f` ≈ 23 s after its peak near 3 s. So the
/// hover is judged from 30 s on, against the 5 cm settling criterion of the SIL summary: the
/// law has no integral action, so a constant unmodelled acceleration `δa` (IMU bias leaking
/// through the velocity filter, pose latency) leaves an offset `δa / k_p`, 1 cm per 0.01 m/s²
/// with the x500's `k_p` = 1/s², nine times the paper gains' (`k_p` = 9/s², for which this test
/// asked 2 cm). Measured: about 2 cm at 100 Hz, 4 cm at 300 Hz with 25 ms latency.
#[test]
fn pose_rates_and_latency() {
    for (rate, latency, dropout) in [(300.0, 0.025, 0.02), (100.0, 0.010, 0.05)] {
        let mut setup = scenarios::pose_loss(11);
        setup.pose_outage = None;
        setup.duration_s = 35.0;
        setup.mocap.rate_hz = rate;
        setup.mocap.latency_s = latency;
        setup.mocap.dropout = dropout;
        setup.flight.mocap_latency_us = (latency * 1e6) as u64;
        let (mut est, mut err) = (0.0f64, 0.0f64);
        let s = run(&setup, |r| {
            if r.t_s > 30.0 {
                est = est.max(r.estimate_error_m);
                err = err.max(r.position_error_m);
            }
        })
        .unwrap();
        assert_eq!(s.final_state, "armed");
        assert!(s.link_frames[0] as f64 > rate * 36.0 * (1.0 - dropout) * 0.95);
        assert!(est < 0.005, "{rate} Hz: estimate error {est}");
        assert!(err < 0.05, "{rate} Hz: position error {err}");
    }
}
