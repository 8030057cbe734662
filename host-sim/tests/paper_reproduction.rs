//! Section VI of the paper, reproduced end to end through host-sim: Theorem 1's thrust interval
//! for Table I, the closed-loop run from the inverted start in f32 and f64 (every sample inside
//! the a-priori bounds, the steady-state claim at t = 30 s), and the helix's Assumption 1
//! constants in closed form.

use approx::assert_relative_eq;
use controller_core::scalar::to_f64;
use controller_core::{
    certify, Certificate, FilterStart, Gains, Limits, ReferenceTrajectory, Trajectory,
    TrajectoryConstants, Vehicle,
};
use core::f64::consts::PI;
use host_sim::fly::sim::{certificate, run, Record, Summary};
use host_sim::model::scenario::{Precision, Scenario};
use nalgebra::Vector3;

/// Rounds to the two decimals the paper prints.
fn printed(x: f64) -> f64 {
    (x * 100.0).round() / 100.0
}

/// The helix frequency of Section VI, `f = 2π/15` rad/s.
fn paper_frequency() -> f64 {
    2.0 * PI / 15.0
}

/// The embedded scenario is Table I and Section VI's vehicle, limits and trajectory: the TOML
/// file and the core's constructors agree exactly (the same decimal literals parse to the same
/// doubles), so the host-sim runs below are the paper's set-up.
#[test]
fn embedded_scenario_is_table_i() {
    let s = Scenario::paper();
    assert_eq!(s.vehicle::<f64>(), Vehicle::paper());
    assert_eq!(s.limits::<f64>(), Limits::paper());
    assert_eq!(s.gains::<f64>(), Gains::paper());
    let from_toml = s.trajectory::<f64>();
    let from_core = ReferenceTrajectory::<f64>::paper_helix();
    for k in 0..40 {
        let t = 0.77 * k as f64;
        // `f` is written as a 17-digit decimal in the TOML and computed as 2π/15 in the core:
        // at most one ulp apart, so the samples agree to a few ulp of their magnitude (≤ 10).
        let (a, b) = (from_toml.sample(t), from_core.sample(t));
        assert_relative_eq!(a.position, b.position, epsilon = 1e-13);
        assert_relative_eq!(a.velocity, b.velocity, epsilon = 1e-13);
        assert_relative_eq!(a.acceleration, b.acceleration, epsilon = 1e-13);
        assert_relative_eq!(a.heading, b.heading, epsilon = 1e-13);
    }
    assert_eq!(s.initial.position_m, [5.0, 5.0, 10.0]);
    assert_eq!(s.initial.euler_deg, [-179.0, 0.0, 100.0]);
    assert_eq!(s.simulation.controller_period_s, 0.01);
}

/// Theorem 1 for Table I: the paper prints `T ≥ 3.51 N` and `T ≤ 6.19 N`. The certificate
/// (f64, as host-sim computes it, and f32, as the MCU would) rounds to those numbers, and equals
/// the closed forms eq:LowerBoundT `m(g − M_p − K_a3)` and eq:UpperBoundT
/// `m(√3 M_p + sqrt(K_a12² + (K_a3 + g)²))` evaluated here with `K_a12 = K_a3 = f²`.
#[test]
fn theorem1_thrust_interval_matches_the_paper() {
    let c = certificate(&Scenario::paper()).unwrap();
    assert_eq!(
        printed(c.bounds.thrust_min),
        3.51,
        "{}",
        c.bounds.thrust_min
    );
    assert_eq!(
        printed(c.bounds.thrust_max),
        6.19,
        "{}",
        c.bounds.thrust_max
    );

    let (m, g, mp) = (0.460, 9.81, 2.0);
    let f2 = paper_frequency().powi(2);
    let t_min = m * (g - mp - f2);
    let t_max = m * (3f64.sqrt() * mp + (f2 * f2 + (f2 + g) * (f2 + g)).sqrt());
    // Same formulas, different operation order: a few roundings of ε/2 each.
    assert_relative_eq!(
        c.bounds.thrust_min,
        t_min,
        max_relative = 16.0 * f64::EPSILON
    );
    assert_relative_eq!(
        c.bounds.thrust_max,
        t_max,
        max_relative = 16.0 * f64::EPSILON
    );

    let c32: Certificate<f32> = certify(
        &Vehicle::paper(),
        &Limits::paper(),
        &Gains::paper(),
        &ReferenceTrajectory::paper_helix().constants(),
        FilterStart::Zero,
    )
    .unwrap();
    assert_eq!(printed(f64::from(c32.bounds.thrust_min)), 3.51);
    assert_eq!(printed(f64::from(c32.bounds.thrust_max)), 6.19);
    // Theorem 1's interval does not depend on where the filters start (only Lemma 1 does).
    let boxed = certify(
        &Vehicle::<f64>::paper(),
        &Limits::paper(),
        &Gains::paper(),
        &ReferenceTrajectory::paper_helix().constants(),
        FilterStart::InSaturationBox,
    )
    .unwrap();
    assert_eq!(boxed.bounds.thrust_min, c.bounds.thrust_min);
    assert_eq!(boxed.bounds.thrust_max, c.bounds.thrust_max);
}

/// The helix's Assumption 1 constants are the closed forms (exact maxima) for
/// `p_d = p̄ + (cos f t, sin f t, cos f t)`, `ψ_d = π sin f t`:
/// `K_a12 = K_a3 = f²`, `K_j = K_s/f = √2 f³`, `K_ν̇ = π f`, `K_ν̈ = π² f²`
/// (for `ψ = A sin f t` with `A = π > 1`, `max sqrt(ψ̈² + ψ̇⁴) = A² f²` at `cos f t = ±1`).
#[test]
fn helix_constants_are_the_closed_form() {
    let f = paper_frequency();
    let expected = [
        f * f,
        f * f,
        2f64.sqrt() * f.powi(3),
        2f64.sqrt() * f.powi(4),
        PI * f,
        PI * PI * f * f,
    ];
    fn as_array<T: controller_core::Scalar>(k: TrajectoryConstants<T>) -> [f64; 6] {
        [
            k.horizontal_acceleration,
            k.vertical_acceleration,
            k.jerk,
            k.snap,
            k.heading_rate,
            k.heading_acceleration,
        ]
        .map(to_f64)
    }
    let from_toml = as_array(Scenario::paper().trajectory::<f64>().constants());
    let from_core = as_array(ReferenceTrajectory::<f64>::paper_helix().constants());
    let from_core32 = as_array(ReferenceTrajectory::<f32>::paper_helix().constants());
    for i in 0..6 {
        // A handful of roundings (and ≤ 1 ulp between the TOML's f and 2π/15): 16 ε.
        assert_relative_eq!(
            from_toml[i],
            expected[i],
            max_relative = 16.0 * f64::EPSILON
        );
        assert_relative_eq!(
            from_core[i],
            expected[i],
            max_relative = 16.0 * f64::EPSILON
        );
        let eps32 = f64::from(f32::EPSILON);
        assert_relative_eq!(from_core32[i], expected[i], max_relative = 16.0 * eps32);
    }
    assert_relative_eq!(
        from_core[3] / f,
        from_core[2],
        max_relative = 16.0 * f64::EPSILON
    );

    // They are maxima, not loose bounds: over one period sampled every 1 ms (which contains
    // t = 0 and t = 3.75 s, where the maxima sit), the sampled maxima equal them to rounding.
    let traj = ReferenceTrajectory::<f64>::paper_helix();
    let mut max = [0.0f64; 6];
    for i in 0..15_000 {
        let s = traj.sample(i as f64 * 1e-3);
        let got = [
            s.acceleration.xy().norm(),
            s.acceleration.z.abs(),
            s.jerk.norm(),
            s.snap.norm(),
            s.heading_rate.norm(),
            s.heading_acceleration.norm(),
        ];
        for (m, g) in max.iter_mut().zip(got) {
            *m = m.max(g);
        }
    }
    for (i, name) in ["K_a12", "K_a3", "K_j", "K_s", "K_nu_dot", "K_nu_ddot"]
        .iter()
        .enumerate()
    {
        assert_relative_eq!(max[i], expected[i], max_relative = 1e-12);
        assert!(max[i] <= expected[i] * (1.0 + 1e-12), "{name}");
    }
}

/// Relative slack for comparing the controller's outputs with the f64 certificate: the thrust
/// and torque come out of a few dozen roundings in the controller's scalar (plus the f32
/// rounding of the parameters themselves, e.g. g = 9.81 is 4e-8 off in f32), so 64 ε of that
/// scalar. The certificate's bounds are closed, so a value on the bound passes.
fn slack(precision: Precision) -> f64 {
    match precision {
        Precision::F32 => 64.0 * f64::from(f32::EPSILON),
        Precision::F64 => 64.0 * f64::EPSILON,
    }
}

fn paper_run(precision: Precision) -> (Summary, Vec<Record>) {
    let mut s = Scenario::paper();
    s.simulation.precision = precision;
    run(&s).unwrap()
}

/// The whole 30 s Section VI run in one precision.
fn check_paper_run(precision: Precision) -> Summary {
    let (summary, records) = paper_run(precision);
    let cert = certificate(&Scenario::paper()).unwrap();
    let b = &cert.bounds;
    let s = slack(precision);

    // 30 s at 10 ms: samples 0..=3000.
    assert_eq!(records.len(), 3001);
    assert_eq!(summary.observed.samples, 3001);

    // The vehicle really started upside down at (5, 5, 10) m: roll −179°, pitch 0, yaw 100°
    // (the scenario's Euler → quaternion → Euler round trip is exact to ~1e-15 rad), body z
    // pointing down (e₃ᵀRe₃ = cos φ cos θ < 0).
    let first = &records[0];
    assert_eq!(first.t_s, 0.0);
    assert_relative_eq!(first.roll_rad, (-179f64).to_radians(), epsilon = 1e-12);
    assert_relative_eq!(first.pitch_rad, 0.0, epsilon = 1e-12);
    assert_relative_eq!(first.yaw_rad, 100f64.to_radians(), epsilon = 1e-12);
    assert!(first.roll_rad.cos() * first.pitch_rad.cos() < -0.999);
    // p_d(0) = p̄ + (cos 0, sin 0, cos 0) = (−2, 1, 5.5) m from the paper's formula.
    let p_d0 = Vector3::new(-3.0, 1.0, 4.5) + Vector3::new(1.0, 0.0, 1.0);
    let p0 = Vector3::new(5.0, 5.0, 10.0);
    assert_relative_eq!(
        Vector3::new(first.x_ref_m, first.y_ref_m, first.z_ref_m),
        p_d0,
        epsilon = 1e-14
    );
    assert_relative_eq!(
        first.position_error_m,
        (p0 - p_d0).norm(),
        max_relative = 1e-15
    );
    // The initial attitude error is nearly 180°: MRP norm tan(θ/4) close to 1.
    assert!(first.mrp_error > 0.95, "{}", first.mrp_error);

    // Every sample inside the a-priori bounds (Theorems 1 and 2), checked here sample by
    // sample and not only through the summary.
    for r in &records {
        assert!(
            r.thrust_N >= b.thrust_min * (1.0 - s) && r.thrust_N <= b.thrust_max * (1.0 + s),
            "t = {}: T = {} N outside [{}, {}]",
            r.t_s,
            r.thrust_N,
            b.thrust_min,
            b.thrust_max
        );
        for (i, tau) in [r.torque_x_Nm, r.torque_y_Nm, r.torque_z_Nm]
            .into_iter()
            .enumerate()
        {
            assert!(
                tau.abs() <= b.torque_max[i] * (1.0 + s),
                "t = {}: |tau_{}| = {} > {}",
                r.t_s,
                i + 1,
                tau.abs(),
                b.torque_max[i]
            );
        }
        // Lemma 1 along the run, and the lifted MRP stays in (1 + δ)𝔹³.
        assert!(r.omega_d_norm_rad_s <= b.angular_velocity * (1.0 + s));
        assert!(r.omega_d_dot_norm_rad_s2 <= b.angular_acceleration * (1.0 + s));
        assert!(r.mrp_error <= 1.02 * (1.0 + s));
    }
    assert_eq!(summary.observed.samples_outside_a_priori_bounds, 0);

    // The paper's z-axis transient: the inverted start makes the vehicle fall below the
    // reference, and the largest position error of the run exceeds the initial one.
    let peak = records
        .iter()
        .max_by(|a, b| a.position_error_m.total_cmp(&b.position_error_m))
        .unwrap();
    assert!(peak.position_error_m > first.position_error_m);
    assert!(peak.z_m < peak.z_ref_m, "peak at t = {} s", peak.t_s);

    // Steady state at t = 30 s: position error < 0.001 m and MRP error < 0.0001 (Section VI).
    let last = records.last().unwrap();
    assert_relative_eq!(last.t_s, 30.0, epsilon = 1e-9);
    assert!(last.position_error_m < 1e-3, "{}", last.position_error_m);
    assert!(last.mrp_error < 1e-4, "{}", last.mrp_error);
    assert_eq!(summary.final_.position_error_m, last.position_error_m);
    assert_eq!(summary.final_.mrp_error, last.mrp_error);

    // The position error stays below 1 mm from some time on, and the summary's settling time
    // is exactly the start of the final run of samples below 1 mm.
    let settle = summary
        .settling
        .position_error_below_1mm_from_s
        .expect("position error must settle below 1 mm");
    let start = records
        .iter()
        .rposition(|r| r.position_error_m >= 1e-3)
        .map_or(0, |i| i + 1);
    assert!(start < records.len());
    assert_eq!(records[start].t_s, settle);
    assert!(settle < 30.0);
    assert!(summary.settling.mrp_error_below_1e_4_from_s.is_some());
    summary
}

#[test]
fn paper_scenario_f32() {
    check_paper_run(Precision::F32);
}

#[test]
fn paper_scenario_f64() {
    check_paper_run(Precision::F64);
}

/// f32 (the MCU's scalar) and f64 reach the same steady state: both final errors are below
/// the paper's thresholds and within a factor 10 of each other. The residual errors are set by
/// the 10 ms sample-and-hold tracking of a moving reference, not by rounding (the f32 rounding
/// floor of the MRP error is ~1e-7, the order of the f64 value itself), so they must agree.
#[test]
fn f32_and_f64_agree() {
    let (a, _) = paper_run(Precision::F32);
    let (b, _) = paper_run(Precision::F64);
    for (x, y) in [
        (a.final_.position_error_m, b.final_.position_error_m),
        (a.final_.mrp_error, b.final_.mrp_error),
    ] {
        assert!(x > 0.0 && y > 0.0);
        let ratio = x / y;
        assert!((0.1..=10.0).contains(&ratio), "f32 {x} vs f64 {y}");
    }
}
