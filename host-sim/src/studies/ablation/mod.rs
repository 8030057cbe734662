//! `host-sim ablation`: the paper's design choices, measured.
//!
//! 1. **Hysteresis.** The hybrid path lifting (`δ > 0`, memory quaternion) against the memoryless
//!    lifting (`q₀ ≥ 0`, principal MRP) on the seven starts exactly 180° from `R_d(0)`, at the
//!    reference position, under attitude measurement noise of several levels. Measured: the
//!    switches of the fed-back attitude error (chattering), the most switches in any 1 s, and
//!    the time until the attitude error first drops below 90° (the time lost at 180°).
//! 2. **Filters.** The filtered outer loop against the same saturated law without the two
//!    filters (`u = ubar_p + g e₃ + p̈_d`), from the paper's start (nominal and with measurement
//!    noise) and from the 180° starts. Measured: peak `|ω_d|`, `|ω̇_d|`, torque and thrust, and
//!    samples outside the a-priori bounds (which only the filtered law is promised).
//!
//! 3. **No-dive thrust.** The paper's `T = m|u|` against a no-dive thrust (the scenario's
//!    `[controller] thrust`, or vertical priority; [`crate::studies::ablation::no_dive`]): altitude lost from the paper's start, upright, and the seven
//!    180° starts (on the reference and at hover); chattering under attitude noise.
//! 4. **Integral action.** The paper's law with and without the bounded integral action under
//!    mass errors, a constant force, gusts and all of them together
//!    ([`crate::studies::ablation::integral`]): steady error, convergence, samples outside the (extended)
//!    a-priori bounds, and recovery from the 180° starts.
//!
//! The first two run in f64 (the recomposed law of [`crate::fly::controllers::ablated`], which equals
//! the core's law bit for bit when nothing is ablated); the third and fourth at the scenario's
//! precision (the core's law itself), so the third's paper-start figure is the main run's.

mod plots;
use plots::write_plots;
mod markdown;
pub use markdown::markdown;
pub mod integral;
pub mod no_dive;

use std::path::PathBuf;

use anyhow::{Context, Result};
use rayon::prelude::*;
use serde::Serialize;

use crate::fly::controllers::ControllerKind;
use crate::model::scenario::{Precision, Scenario};
use crate::runs::metrics::{BoundSet, RunMetrics};
use crate::runs::runner::{bound_set, run_one};
use crate::runs::sampler::{run_seed, Sampler, SamplerRadii, HALF_TURN_AXES};
use crate::runs::stats::Distribution;
use crate::runs::trace::{trace, TracePoint};
use crate::studies::ablation::integral::{run_integral, IntegralReport};
use crate::studies::ablation::no_dive::{run_no_dive, NoDiveReport};
use crate::studies::campaign::options::BaseOptions;
use crate::studies::campaign::Convergence;

/// Attitude noise levels of the hysteresis ablation [deg, std per axis].
pub const NOISE_LEVELS_DEG: [f64; 3] = [0.0, 1.0, 3.0];

/// One cell of the hysteresis table.
#[derive(Clone, Debug, Serialize)]
pub struct HysteresisRow {
    /// `"paper"` (hybrid) or `"paper_memoryless"`.
    pub lifting: String,
    /// Attitude noise std \[deg\].
    pub attitude_noise_deg: f64,
    /// Runs.
    pub runs: usize,
    /// Switches per run.
    pub switches_per_run: Distribution,
    /// Largest number of switches in any 1 s over the runs.
    pub max_switches_in_1s: u32,
    /// Time until the attitude error is first below 90° \[s\].
    pub time_to_90deg_s: Distribution,
    /// Runs converged.
    pub converged: usize,
}

/// One row of the filter table.
#[derive(Clone, Debug, Serialize)]
#[allow(non_snake_case)]
pub struct FilterRow {
    /// The case (start and noise).
    pub case: String,
    /// `"paper"` or `"paper_no_filter"`.
    pub law: String,
    /// Largest `|ω_d|` [rad/s].
    pub omega_d_max_rad_s: f64,
    /// Largest `|ω̇_d|` [rad/s²].
    pub omega_d_dot_max_rad_s2: f64,
    /// Largest `|τ_i|` per axis [N m].
    pub torque_abs_max_Nm: [f64; 3],
    /// Thrust range \[N\].
    pub thrust_range_N: [f64; 2],
    /// Samples outside the a-priori bounds.
    pub samples_outside_a_priori: u64,
    /// Samples beyond the physical limits.
    pub samples_beyond_limits: u64,
    /// Settling time \[s\] (largest over the case's runs; `None` if one did not settle).
    pub settling_time_s: Option<f64>,
}

/// `ablation.json`.
#[derive(Clone, Debug, Serialize)]
pub struct AblationReport {
    /// Definitions of the measured quantities.
    pub definitions: String,
    /// The a-priori bounds and limits.
    pub bounds: BoundSet,
    /// The plant every run flies (`"ideal"` or `"rotors"`).
    pub plant: crate::model::scenario::PlantKind,
    /// Hysteresis ablation.
    pub hysteresis: Vec<HysteresisRow>,
    /// Filter ablation.
    pub filters: Vec<FilterRow>,
    /// No-dive thrust against the paper's.
    pub no_dive_thrust: NoDiveReport,
    /// The paper's law with and without the integral action.
    pub integral_action: IntegralReport,
}

const LAWS: [ControllerKind; 2] = [ControllerKind::Paper, ControllerKind::PaperMemoryless];

fn hysteresis(
    scenario: &Scenario,
    seed: u64,
    repeats: u64,
    bounds: BoundSet,
    convergence: Convergence,
) -> Result<Vec<HysteresisRow>> {
    let radii = SamplerRadii {
        position_m: 0.0,
        velocity_m_s: 0.0,
        angular_velocity_rad_s: 0.0,
    };
    let sampler = Sampler::new(scenario, radii)?;
    let axes = HALF_TURN_AXES.len() as u64;
    let mut rows = Vec::new();
    for noise in NOISE_LEVELS_DEG {
        let mut s = scenario.clone();
        s.perturbations.attitude_noise_std_rad = noise.to_radians();
        for law in LAWS {
            let runs: Vec<RunMetrics> = (0..repeats * axes)
                .into_par_iter()
                .filter_map(|i| {
                    let seed = run_seed(seed, i);
                    let initial = sampler.sample(i % axes, seed, true);
                    run_one(&s, law, i, seed, &initial, convergence, bounds).metrics
                })
                .collect();
            rows.push(HysteresisRow {
                lifting: law.label().into(),
                attitude_noise_deg: noise,
                runs: runs.len(),
                switches_per_run: Distribution::of(runs.iter().map(|m| f64::from(m.switches))),
                max_switches_in_1s: runs
                    .iter()
                    .map(|m| m.max_switches_per_1s)
                    .max()
                    .unwrap_or(0),
                time_to_90deg_s: Distribution::of(
                    runs.iter().filter_map(|m| m.attitude_below_90deg_s),
                ),
                converged: runs.iter().filter(|m| m.converged).count(),
            });
        }
    }
    Ok(rows)
}

type Traces = Vec<(String, ControllerKind, Vec<TracePoint>)>;

fn filters(
    scenario: &Scenario,
    seed: u64,
    bounds: BoundSet,
    convergence: Convergence,
) -> Result<(Vec<FilterRow>, Traces)> {
    let mut noisy = scenario.clone();
    noisy.perturbations.position_noise_std_m = 0.01;
    noisy.perturbations.velocity_noise_std_m_s = 0.05;
    noisy.perturbations.attitude_noise_std_rad = 0.5f64.to_radians();
    noisy.perturbations.gyro_noise_std_rad_s = 0.01;
    let laws = [ControllerKind::Paper, ControllerKind::PaperNoFilter];
    let mut rows = Vec::new();
    let mut traces = Vec::new();
    for (case, s) in [
        ("paper start, nominal", scenario),
        (
            "paper start, noise (p 1 cm, v 5 cm/s, R 0.5 deg, gyro 0.01 rad/s)",
            &noisy,
        ),
    ] {
        for law in laws {
            let (m, points) = trace(s, law, &s.initial_state(), seed, convergence, bounds)
                .with_context(|| format!("{case}, {}", law.label()))?;
            rows.push(row(case, law, std::slice::from_ref(&m)));
            if case.ends_with("nominal") {
                traces.push((case.to_string(), law, points));
            }
        }
    }
    let sampler = Sampler::new(scenario, SamplerRadii::default())?;
    for law in laws {
        let runs: Vec<RunMetrics> = (0..HALF_TURN_AXES.len() as u64)
            .into_par_iter()
            .filter_map(|i| {
                let seed = run_seed(seed, i);
                let initial = sampler.sample(i, seed, true);
                run_one(scenario, law, i, seed, &initial, convergence, bounds).metrics
            })
            .collect();
        rows.push(row("seven 180-deg starts, 10 m ball (worst)", law, &runs));
    }
    Ok((rows, traces))
}

fn row(case: &str, law: ControllerKind, runs: &[RunMetrics]) -> FilterRow {
    let max = |f: fn(&RunMetrics) -> f64| runs.iter().map(f).fold(0.0, f64::max);
    FilterRow {
        case: case.into(),
        law: law.label().into(),
        omega_d_max_rad_s: max(|m| m.omega_d_max_rad_s),
        omega_d_dot_max_rad_s2: max(|m| m.omega_d_dot_max_rad_s2),
        torque_abs_max_Nm: std::array::from_fn(|i| {
            runs.iter()
                .map(|m| m.torque_abs_max_Nm[i])
                .fold(0.0, f64::max)
        }),
        thrust_range_N: [
            runs.iter()
                .map(|m| m.thrust_min_N)
                .fold(f64::INFINITY, f64::min),
            max(|m| m.thrust_max_N),
        ],
        samples_outside_a_priori: runs.iter().map(|m| m.samples_outside_a_priori).sum(),
        samples_beyond_limits: runs.iter().map(|m| m.samples_beyond_limits).sum(),
        settling_time_s: runs
            .iter()
            .map(|m| m.settling_time_s)
            .try_fold(0.0f64, |acc, s| s.map(|s| acc.max(s))),
    }
}

/// How many runs the integral action's cells fly (`--integral-runs`,
/// `--integral-combined-runs`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct IntegralRuns {
    /// Runs per cell.
    pub runs: u64,
    /// Runs per cell of the combined case.
    pub combined: u64,
}

/// Runs the ablations on `scenario` (precision forced to f64 for the first two).
///
/// Errors: the scenario is invalid or a traced run fails.
pub fn run_ablation(
    scenario: &Scenario,
    seed: u64,
    repeats: u64,
    integral_runs: IntegralRuns,
) -> Result<(AblationReport, Traces)> {
    let no_dive_thrust = run_no_dive(scenario, seed, repeats)?;
    let integral_action = run_integral(scenario, seed, integral_runs.runs, integral_runs.combined)?;
    let mut scenario = scenario.clone();
    scenario.simulation.precision = Precision::F64;
    let bounds = bound_set(&scenario)?;
    let convergence = Convergence::default();
    let hysteresis = hysteresis(&scenario, seed, repeats, bounds, convergence)?;
    let (filters, traces) = filters(&scenario, seed, bounds, convergence)?;
    Ok((
        AblationReport {
            definitions: format!(
                "switches: jumps of the fed-back attitude error (hybrid: MRP flips; memoryless: \
                 changes of the q0 >= 0 hemisphere). time_to_90deg_s: first time the true \
                 attitude error is below 90 deg. {}",
                convergence.describe()
            ),
            bounds,
            plant: scenario.simulation.plant,
            hysteresis,
            filters,
            no_dive_thrust,
            integral_action,
        },
        traces,
    ))
}

/// What the `ablation` job runs (the command line's defaults in parentheses).
#[derive(Clone, Debug, PartialEq)]
pub struct AblationOptions {
    /// Output directory, created; files overwritten (`out/ablation`).
    pub out: PathBuf,
    /// Repetitions of the seven 180° starts per noise level, hysteresis ablation (4).
    pub repeats: u64,
    /// Runs of the integral action's cells (200 each).
    pub integral_runs: IntegralRuns,
    /// Scenario, seed and overrides.
    pub base: BaseOptions,
}

/// `host-sim ablation`: runs both ablations, writes `ablation.md`, `ablation.json` and plots.
///
/// Errors: invalid scenario, a failed run, or a file that cannot be written.
pub fn run_command(args: &AblationOptions) -> Result<()> {
    let scenario = args.base.scenario()?;
    let (report, traces) =
        run_ablation(&scenario, args.base.seed, args.repeats, args.integral_runs)?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let plots = write_plots(&args.out, &report, &traces)?;
    let md = markdown(&report, &plots);
    let written: Vec<PathBuf> = vec![args.out.join("ablation.md"), args.out.join("ablation.json")];
    std::fs::write(&written[0], &md)
        .with_context(|| format!("writing {}", written[0].display()))?;
    std::fs::write(&written[1], serde_json::to_string_pretty(&report)? + "\n")
        .with_context(|| format!("writing {}", written[1].display()))?;
    print!("{md}");
    println!(
        "Wrote ablation.md, ablation.json and {} plots to {}",
        plots.len(),
        args.out.display()
    );
    Ok(())
}
