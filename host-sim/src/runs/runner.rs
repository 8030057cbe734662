//! Runs a campaign: N closed-loop runs in parallel (rayon), each from its own seed, with a
//! progress bar (indicatif, on stderr; hidden when stderr is not a terminal).

use std::ops::Range;

use anyhow::Result;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::metrics::{BoundSet, Convergence, MetricsAccumulator, RunMetrics};
use super::sampler::{run_seed, InitialCondition, Sampler, SamplerRadii};
use crate::fly::closed_loop::{fly, PlantModel};
use crate::fly::controllers::ControllerKind;
use crate::model::scenario::Scenario;

/// What a campaign runs.
#[derive(Clone, Debug)]
pub struct CampaignConfig {
    /// The base scenario (vehicle, gains, trajectory, simulation, perturbations); its
    /// `[initial]` table is replaced by the sampled initial conditions.
    pub scenario: Scenario,
    /// Controller flown in every run.
    pub controller: ControllerKind,
    /// Number of runs.
    pub runs: u64,
    /// Campaign seed.
    pub seed: u64,
    /// Offset ball radii.
    pub radii: SamplerRadii,
    /// Include the fixed 180° starts as the first runs.
    pub half_turns: bool,
    /// Convergence thresholds.
    pub convergence: Convergence,
    /// Show a progress bar on stderr (only drawn when stderr is a terminal).
    pub progress: bool,
    /// Worker threads; `None`: rayon's default (one per core). Results do not depend on it.
    pub threads: Option<usize>,
}

/// One run's result.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RunResult {
    /// Run index.
    pub index: u64,
    /// The run's seed (`run_seed(campaign seed, index)`).
    pub seed: u64,
    /// `"haar"` or `"half_turn_<axis>"`.
    pub start: String,
    /// Initial angle from `R_d(0)` \[deg\].
    pub initial_attitude_error_deg: f64,
    /// Initial `|p − p_d|` \[m\].
    pub initial_position_error_m: f64,
    /// The metrics; `None` when the controller refused a sample.
    pub metrics: Option<RunMetrics>,
    /// Why the run stopped early, if it did.
    pub error: Option<String>,
}

/// The bounds of a scenario: the certificate's a-priori bounds (with the no-dive thrust, its
/// thrust interval `[T_floor, T_max]` instead of Theorem 1's), the tight bounds and the physical
/// limits.
///
/// Errors: the certificate cannot be computed (invalid parameters), or the no-dive floor is
/// above Theorem 1's `T_min`.
pub fn bound_set(scenario: &Scenario) -> Result<BoundSet> {
    let tight = crate::bounds::certificate::scenario_tight_bounds(scenario)?;
    Ok(BoundSet {
        tight: Some(crate::bounds::certificate::tight_limits(&tight)),
        ..paper_bound_set(scenario)?
    })
}

/// [`bound_set`] without the tight bounds (their branch and bound takes about a second): for
/// the design search, which flies thousands of candidate gains.
///
/// Errors: as [`bound_set`].
pub fn paper_bound_set(scenario: &Scenario) -> Result<BoundSet> {
    // The airmode interval of the Minkowski sum, as `design` writes it into the flight file
    // (docs/torque-set.md): the attitude terms' joint bound is not built for each run.
    let cert = crate::bounds::certificate::scenario_certificate_without_joint_bound(scenario)?;
    let [thrust_low, thrust_high] = scenario
        .thrust_interval(&cert)
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    Ok(BoundSet {
        thrust_min_N: thrust_low,
        thrust_max_N: thrust_high,
        torque_max_Nm: cert.torque_max_all().into(),
        limit_thrust_N: scenario.limits.thrust_max_N,
        limit_torque_Nm: scenario.limits.torque_max_Nm,
        tight: None,
    })
}

/// Flies one run from `initial` and measures it. A refused sample ends the run with an error
/// in the result (the campaign continues).
pub fn run_one(
    scenario: &Scenario,
    controller: ControllerKind,
    index: u64,
    seed: u64,
    initial: &InitialCondition,
    convergence: Convergence,
    bounds: BoundSet,
) -> RunResult {
    let sim = &scenario.simulation;
    let mut acc =
        MetricsAccumulator::new(convergence, bounds, sim.duration_s, sim.controller_period_s);
    // A different stream from the sampler's: the perturbations must not reuse its draws.
    let noise_seed = run_seed(seed, u64::MAX);
    let outcome = controller.build(scenario).and_then(|mut c| {
        fly(scenario, c.as_mut(), &initial.state, noise_seed, |s| {
            acc.push(s)
        })
    });
    let reference = scenario.trajectory::<f64>();
    let p0 = controller_core::Trajectory::sample(&reference, 0.0).position;
    let (metrics, error) = match outcome {
        Ok(_) => (Some(acc.finish()), None),
        Err(e) => (None, Some(format!("{e:#}"))),
    };
    RunResult {
        index,
        seed,
        start: initial.kind.label(),
        initial_attitude_error_deg: initial.attitude_error_deg,
        initial_position_error_m: (initial.state.position - p0).norm(),
        metrics,
        error,
    }
}

/// Runs the campaign; results in run order.
///
/// Errors: the scenario is invalid (bounds or `R_d(0)` undefined).
pub fn run_campaign(config: &CampaignConfig) -> Result<Vec<RunResult>> {
    run_campaign_runs(config, 0..config.runs)
}

/// Runs the campaign's runs `indices` only (a shard, [`crate::studies::campaign::shard::Shard::runs`]); results
/// in run order, each exactly as in the whole campaign (a run depends only on the campaign seed
/// and its index).
///
/// Errors: as [`run_campaign`].
pub fn run_campaign_runs(config: &CampaignConfig, indices: Range<u64>) -> Result<Vec<RunResult>> {
    run_campaign_runs_within(config, indices, bound_set(&config.scenario)?)
}

/// [`run_campaign_runs`] against the campaign's bound set computed once by the caller
/// ([`bound_set`] of `config.scenario`: the tight bounds' branch and bound takes about a second,
/// and the caller reports the same set).
///
/// Errors: as [`run_campaign`].
pub fn run_campaign_runs_within(
    config: &CampaignConfig,
    indices: Range<u64>,
    bounds: BoundSet,
) -> Result<Vec<RunResult>> {
    // A plant that cannot be built would fail every run: refuse the campaign instead.
    PlantModel::of(&config.scenario, &config.scenario.perturbations)?;
    let sampler = Sampler::new(&config.scenario, config.radii)?;
    let bar = if config.progress {
        let bar = ProgressBar::with_draw_target(
            Some(indices.end - indices.start),
            ProgressDrawTarget::stderr(),
        );
        if let Ok(style) = ProgressStyle::with_template(
            "{prefix} [{elapsed_precise}] {wide_bar} {pos}/{len} runs ({per_sec}, eta {eta})",
        ) {
            bar.set_style(style);
        }
        bar.set_prefix(config.controller.label());
        bar
    } else {
        ProgressBar::hidden()
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(config.threads.unwrap_or(0))
        .build()?;
    let results = pool.install(|| runs_in_parallel(config, indices, &sampler, bounds, &bar));
    bar.finish_and_clear();
    Ok(results)
}

fn runs_in_parallel(
    config: &CampaignConfig,
    indices: Range<u64>,
    sampler: &Sampler,
    bounds: BoundSet,
    bar: &ProgressBar,
) -> Vec<RunResult> {
    indices
        .into_par_iter()
        .map(|index| {
            let seed = run_seed(config.seed, index);
            let initial = sampler.sample(index, seed, config.half_turns);
            let r = run_one(
                &config.scenario,
                config.controller,
                index,
                seed,
                &initial,
                config.convergence,
                bounds,
            );
            bar.inc(1);
            r
        })
        .collect()
}
