//! Host (criterion) timings of the two steps `firmware/qemu/bench.sh` counts on the emulated
//! Cortex-M4F, through the same functions of `firmware::step_inputs`:
//!
//! - `full_step`: one flight tick of the sequence (10 IMU samples, an `ATT_POS_MOCAP` frame,
//!   `control_tick`), [`step_inputs::full_step`];
//! - `controller_step`: `Controller::step` alone along the same trajectory,
//!   [`step_inputs::controller_step`].
//!
//! Each iteration is the next flight tick of the sequence: the pipeline (or controller) is
//! brought to the arming point outside the timed region, then the [`FLIGHT_TICKS`] flight steps
//! are timed back to back, and again from a fresh pipeline if criterion asks for more. So a
//! figure is the mean over the flight steps, not one step repeated.
//!
//! Run with `cargo bench -p firmware --bench steps` (release profile, fat LTO).

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, Criterion};
use firmware::step_inputs::{
    self, ControllerInputs, Phase, StepInputs, StepSequence, FLIGHT_TICKS,
};

fn full_step(c: &mut Criterion) {
    let inputs: Vec<StepInputs> = StepSequence::new().collect();
    let setup: Vec<&StepInputs> = inputs.iter().filter(|i| i.phase != Phase::Flight).collect();
    let flight: Vec<&StepInputs> = inputs.iter().filter(|i| i.phase == Phase::Flight).collect();
    let mut group = c.benchmark_group("m4f_steps");
    group
        .sample_size(30)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    group.bench_function("full_step", |b| {
        b.iter_custom(|iters| {
            let mut total = Duration::ZERO;
            let mut done = 0u64;
            while done < iters {
                let mut p = step_inputs::new_pipeline();
                for i in &setup {
                    step_inputs::full_step(&mut p, i);
                }
                let n = (iters - done).min(flight.len() as u64) as usize;
                let start = Instant::now();
                for i in &flight[..n] {
                    black_box(step_inputs::full_step(&mut p, black_box(i)));
                }
                total += start.elapsed();
                done += n as u64;
            }
            total
        })
    });
    let controller: Vec<ControllerInputs> = (1..=FLIGHT_TICKS)
        .map(step_inputs::controller_inputs)
        .collect();
    group.bench_function("controller_step", |b| {
        b.iter_custom(|iters| {
            let mut total = Duration::ZERO;
            let mut done = 0u64;
            while done < iters {
                let mut ctl = step_inputs::new_controller();
                let n = (iters - done).min(controller.len() as u64) as usize;
                let start = Instant::now();
                for i in &controller[..n] {
                    let _ = black_box(step_inputs::controller_step(&mut ctl, black_box(i)));
                }
                total += start.elapsed();
                done += n as u64;
            }
            total
        })
    });
    group.finish();
}

criterion_group!(benches, full_step);
criterion_main!(benches);
