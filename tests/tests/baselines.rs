//! The baselines on their own (hover, steps), before they are compared; and the 180° behaviour
//! that sets the paper's law apart.

use host_sim::campaign::metrics::{BoundSet, Convergence, RunMetrics};
use host_sim::campaign::runner::{bound_set, run_one};
use host_sim::campaign::sampler::{run_seed, Sampler, SamplerRadii, HALF_TURN_AXES};
use host_sim::campaign::trace::trace;
use host_sim::controllers::ControllerKind;
use host_sim::plant::RigidBodyState;
use host_sim::scenario::Scenario;
use nalgebra::{UnitQuaternion, Vector3};
use tests::hover_scenario;

const POINT: [f64; 3] = [0.0, 0.0, 5.0];

fn hover(duration_s: f64, clip: bool) -> Scenario {
    let mut s = hover_scenario(POINT, 0.0);
    s.simulation.duration_s = duration_s;
    s.simulation.clip_to_limits = clip;
    s
}

fn start(offset: Vector3<f64>, attitude: UnitQuaternion<f64>) -> RigidBodyState {
    RigidBodyState {
        position: Vector3::from(POINT) + offset,
        velocity: Vector3::zeros(),
        attitude,
        angular_velocity: Vector3::zeros(),
    }
}

fn fly(s: &Scenario, c: ControllerKind, initial: RigidBodyState) -> RunMetrics {
    let conv = Convergence {
        after_s: s.simulation.duration_s,
        ..Convergence::default()
    };
    trace(s, c, &initial, 0, conv, bounds(s)).unwrap().0
}

fn bounds(s: &Scenario) -> BoundSet {
    bound_set(s).unwrap()
}

#[test]
fn each_controller_holds_hover_exactly() {
    let s = hover(5.0, false);
    for c in [
        ControllerKind::Lee,
        ControllerKind::Px4,
        ControllerKind::Paper,
    ] {
        let m = fly(&s, c, start(Vector3::zeros(), UnitQuaternion::identity()));
        assert!(
            m.final_position_error_m < 1e-6,
            "{c:?}: {}",
            m.final_position_error_m
        );
        assert!(m.final_attitude_error_deg < 1e-3, "{c:?}");
        // Hover thrust is m g = 4.513 N.
        assert!(
            (m.thrust_max_N - 0.46 * 9.81).abs() < 1e-3,
            "{c:?}: {}",
            m.thrust_max_N
        );
        assert_eq!(m.samples_beyond_limits, 0, "{c:?}");
    }
}

#[test]
fn lee_settles_a_1m_step_and_a_30deg_tilt() {
    let s = hover(10.0, false);
    let step = fly(
        &s,
        ControllerKind::Lee,
        start(Vector3::x(), UnitQuaternion::identity()),
    );
    // ω_n = 4 rad/s, ζ = 0.7: inside 5 cm after about 1.1 s.
    let t = step.settling_time_s.unwrap();
    assert!(t < 1.5, "step settling {t}");
    assert!(step.final_position_error_m < 1e-9);
    let tilt = UnitQuaternion::from_euler_angles(30f64.to_radians(), 0.0, 0.0);
    let m = fly(&s, ControllerKind::Lee, start(Vector3::zeros(), tilt));
    assert!(m.settling_time_s.unwrap() < 1.5, "{:?}", m.settling_time_s);
    // k_R e_R = 0.15 N m plus the feedforward of Ω̇_d: about 0.36 N m, inside the 0.5 N m limit.
    assert!(m.torque_abs_max_Nm[0] < 0.5, "{:?}", m.torque_abs_max_Nm);
    assert_eq!(m.samples_beyond_limits, 0);
}

#[test]
fn px4_cascade_settles_steps_within_its_limits() {
    let s = hover(10.0, false);
    let step = fly(
        &s,
        ControllerKind::Px4,
        start(Vector3::x(), UnitQuaternion::identity()),
    );
    let t = step.settling_time_s.unwrap();
    assert!(t < 5.0, "step settling {t}");
    assert!(
        step.final_position_error_m < 0.01,
        "{}",
        step.final_position_error_m
    );
    // The cascade clips its own outputs: never beyond the physical limits.
    assert_eq!(step.samples_beyond_limits, 0);
    let tilt = UnitQuaternion::from_euler_angles(30f64.to_radians(), 0.0, 0.0);
    let m = fly(&s, ControllerKind::Px4, start(Vector3::zeros(), tilt));
    assert!(m.settling_time_s.unwrap() < 6.0, "{:?}", m.settling_time_s);
    assert_eq!(m.samples_beyond_limits, 0);
}

/// Lee et al.'s attitude error `e_R` vanishes exactly 180° away: from upside down at hover, with
/// clipped thrust (the commanded `T = F·Re₃ < 0` is cut to 0) and no noise, nothing turns the
/// vehicle. The paper's law turns it below 90° within half a second.
#[test]
fn lee_stays_at_180_degrees_where_the_paper_law_recovers() {
    let s = hover(3.0, true);
    let flipped = UnitQuaternion::from_euler_angles(std::f64::consts::PI, 0.0, 0.0);
    let lee = fly(&s, ControllerKind::Lee, start(Vector3::zeros(), flipped));
    assert_eq!(lee.attitude_below_90deg_s, None);
    assert!(
        lee.final_attitude_error_deg > 179.0,
        "{}",
        lee.final_attitude_error_deg
    );
    let paper = fly(&s, ControllerKind::Paper, start(Vector3::zeros(), flipped));
    let t = paper.attitude_below_90deg_s.unwrap();
    assert!(t < 0.6, "{t}");
}

/// Under attitude noise at 180°, the memoryless sign choices (PX4's `w ≥ 0`, the paper law with
/// `q₀ ≥ 0`) switch far more often than the hybrid lifting.
#[test]
fn memoryless_signs_chatter_more_than_the_hybrid_lifting() {
    let mut s = Scenario::paper();
    s.simulation.duration_s = 5.0;
    s.simulation.precision = host_sim::scenario::Precision::F64;
    s.perturbations.attitude_noise_std_rad = 3f64.to_radians();
    let zero = SamplerRadii {
        position_m: 0.0,
        velocity_m_s: 0.0,
        angular_velocity_rad_s: 0.0,
    };
    let sampler = Sampler::new(&s, zero).unwrap();
    let b = bounds(&s);
    let total = |c: ControllerKind| -> u32 {
        (0..2 * HALF_TURN_AXES.len() as u64)
            .map(|i| {
                let seed = run_seed(5, i);
                let initial = sampler.sample(i % HALF_TURN_AXES.len() as u64, seed, true);
                run_one(&s, c, i, seed, &initial, Convergence::default(), b)
                    .metrics
                    .unwrap()
                    .switches
            })
            .sum()
    };
    let hybrid = total(ControllerKind::Paper);
    let memoryless = total(ControllerKind::PaperMemoryless);
    let px4 = total(ControllerKind::Px4);
    assert!(
        memoryless > 2 * hybrid,
        "memoryless {memoryless}, hybrid {hybrid}"
    );
    assert!(px4 > 2 * hybrid, "px4 {px4}, hybrid {hybrid}");
}
