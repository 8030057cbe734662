//! Benchmarks: one controller step (f32 and f64) at a representative state, and the whole 30 s
//! Section VI closed-loop simulation (f32 and f64 controller), without any file output: with a
//! [`Record`](host_sim::fly::sim::Record) per sample handed to an observer (what the main run writes
//! to `timeseries.csv`), and for the summary only; and the certified joint bound of tilt
//! priority's attitude terms, which `certify` builds.
//!
//! Run with `cargo bench -p host-sim`; sample sizes and times are kept small so the run takes
//! well under two minutes on two cores (after the build).

use std::hint::black_box;
use std::time::Duration;

use controller_core::scalar::{lit, to_f64, Scalar};
use controller_core::torque_set::attitude_joint::{AttitudeJoint, JOINT_SLABS};
use controller_core::{
    ControlOutput, Controller, ReferenceSample, StepError, Trajectory, VehicleState,
};
use criterion::{criterion_group, criterion_main, Criterion};
use host_sim::fly::controllers::measure;
use host_sim::fly::sim::{run_summary, run_with};
use host_sim::model::plant::PlantInput;
use host_sim::model::scenario::{Precision, Scenario};
use nalgebra::Vector3;

/// The controller, the measured state and the reference of the paper scenario at
/// `t = samples · 10 ms`, reached by flying the closed loop (so the filters, the path lifting
/// memory and the state are those of a real flight).
struct Snapshot<T: Scalar> {
    controller: Controller<T>,
    state: VehicleState<T>,
    reference: ReferenceSample<T>,
    dt: T,
}

fn snapshot<T: Scalar>(samples: usize) -> Snapshot<T> {
    let s = Scenario::paper();
    let trajectory = s.trajectory::<T>();
    let mut controller = Controller::new(s.vehicle::<T>(), s.gains::<T>(), &trajectory.constants())
        .expect("the paper's parameters are valid");
    let plant = s.plant();
    let mut state = s.initial_state();
    let dt = s.simulation.controller_period_s;
    for k in 0..samples {
        let out = controller
            .step(
                &measure(&state),
                &trajectory.sample(lit(k as f64 * dt)),
                lit(dt),
            )
            .expect("the paper run is accepted");
        let input = PlantInput {
            thrust: to_f64(out.thrust),
            torque: Vector3::new(
                to_f64(out.torque.x),
                to_f64(out.torque.y),
                to_f64(out.torque.z),
            ),
            ..Default::default()
        };
        state = plant.advance(&state, &input, dt, s.simulation.plant_step_s);
    }
    Snapshot {
        controller,
        state: measure(&state),
        reference: trajectory.sample(lit(samples as f64 * dt)),
        dt: lit(dt),
    }
}

fn step<T: Scalar>(snap: &Snapshot<T>) -> Result<ControlOutput<T>, StepError> {
    // `Controller` is `Copy`: each iteration steps a fresh copy of the same state.
    let mut controller = black_box(snap.controller);
    controller.step(
        black_box(&snap.state),
        black_box(&snap.reference),
        black_box(snap.dt),
    )
}

/// One controller step at t = 1 s of the paper scenario (mid-recovery: saturations active,
/// path lifting already reset once or more).
fn controller_step(c: &mut Criterion) {
    let s32 = snapshot::<f32>(100);
    let s64 = snapshot::<f64>(100);
    let mut group = c.benchmark_group("controller_step");
    group
        .sample_size(50)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    group.bench_function("f32", |b| b.iter(|| step(&s32)));
    group.bench_function("f64", |b| b.iter(|| step(&s64)));
    group.finish();
}

/// The whole 30 s paper scenario: 3001 controller samples and 30 000 RK4 plant steps.
fn paper_scenario(c: &mut Criterion) {
    let mut group = c.benchmark_group("paper_scenario_30s");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(4));
    for (name, precision) in [("f32", Precision::F32), ("f64", Precision::F64)] {
        let mut s = Scenario::paper();
        s.simulation.precision = precision;
        group.bench_function(name, |b| {
            b.iter(|| {
                run_with(black_box(&s), |r| {
                    black_box(r);
                })
            })
        });
    }
    group.finish();
}

/// The same 30 s run for its summary only (`sim::run_summary`: no per-sample record).
fn paper_scenario_summary(c: &mut Criterion) {
    let mut group = c.benchmark_group("paper_scenario_30s_summary");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(4));
    for (name, precision) in [("f32", Precision::F32), ("f64", Precision::F64)] {
        let mut s = Scenario::paper();
        s.simulation.precision = precision;
        group.bench_function(name, |b| b.iter(|| run_summary(black_box(&s))));
    }
    group.finish();
}

/// The certified joint bound of tilt priority's attitude terms on the x500 design's gains
/// (`certify` builds it once per certificate: at boot and on a `PARAM_SET` on the board), on the
/// certified grid and on the grid of `design`'s turn-over refinement (a quarter as fine).
fn attitude_joint(c: &mut Criterion) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("designs/x500/scenario.toml");
    let s = Scenario::load(&path).expect("the x500 design's scenario loads");
    let mut group = c.benchmark_group("attitude_joint");
    group
        .sample_size(20)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    for slabs in [JOINT_SLABS, JOINT_SLABS / 4] {
        let g64 = s.gains::<f64>();
        let g32 = s.gains::<f32>();
        let (t64, t32) = (
            g64.tilt_priority.expect("the x500 flies tilt priority"),
            g32.tilt_priority.expect("the x500 flies tilt priority"),
        );
        group.bench_function(format!("f64_{slabs}"), |b| {
            b.iter(|| {
                AttitudeJoint::of(
                    black_box(&t64),
                    g64.attitude.mrp_saturation,
                    g64.attitude.k_mrp,
                    g64.hysteresis,
                    slabs,
                )
            })
        });
        group.bench_function(format!("f32_{slabs}"), |b| {
            b.iter(|| {
                AttitudeJoint::of(
                    black_box(&t32),
                    g32.attitude.mrp_saturation,
                    g32.attitude.k_mrp,
                    g32.hysteresis,
                    slabs,
                )
            })
        });
    }
    group.finish();
}

criterion_group!(
    benches,
    controller_step,
    paper_scenario,
    paper_scenario_summary,
    attitude_joint
);
criterion_main!(benches);
