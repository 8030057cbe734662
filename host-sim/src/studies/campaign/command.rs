//! The `campaign` job: runs a campaign from [`CampaignOptions`] (or one shard of it), prints a
//! short summary and writes the files; and `campaign merge`, which writes the same files from
//! the shards.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Result};

use super::merge::merge_dirs;
use super::options::CampaignOptions;
use super::output::{write_campaign, CampaignReport};
use super::partial::{write_partial, CampaignSetup, PartialResult, SHARD_FORMAT};
use crate::output::fmt_opt;
use crate::runs::metrics::BoundSet;
use crate::runs::metrics::Convergence;
use crate::runs::runner::{
    bound_set, run_campaign_runs, run_campaign_runs_within, CampaignConfig, RunResult,
};
use crate::runs::sampler::SamplerRadii;
use crate::runs::stats::summarise;

/// `host-sim campaign`: runs the campaign, prints a short summary, writes the files; with a
/// shard, runs only its share and writes its `shard.json`.
///
/// Errors: invalid options or scenario; a file cannot be written.
pub fn run_command(args: &CampaignOptions) -> Result<()> {
    let scenario = args.base.scenario()?;
    let duration = scenario.simulation.duration_s;
    let after_s = args
        .converged_after_s
        .unwrap_or_else(|| Convergence::for_duration(duration).after_s);
    if !(after_s.is_finite() && after_s >= 0.0 && after_s <= duration) {
        bail!("--converged-after-s ({after_s}) is not within the run (0 to {duration} s)");
    }
    let config = CampaignConfig {
        scenario,
        controller: args.controller,
        runs: args.runs,
        seed: args.base.seed,
        radii: SamplerRadii {
            position_m: args.position_radius_m,
            velocity_m_s: args.velocity_radius_m_s,
            angular_velocity_rad_s: args.angular_velocity_radius_rad_s,
        },
        half_turns: args.half_turns,
        convergence: Convergence {
            position_m: args.converged_position_m,
            attitude_deg: args.converged_attitude_deg,
            after_s,
        },
        progress: true,
        threads: args.threads,
    };
    let start = Instant::now();
    if let Some(shard) = args.shard {
        let indices = shard.runs(config.runs);
        let results = run_campaign_runs(&config, indices.clone())?;
        let wall_time_s = start.elapsed().as_secs_f64();
        let converged = results
            .iter()
            .filter(|r| r.metrics.as_ref().is_some_and(|m| m.converged))
            .count();
        let path = write_partial(
            &args.out,
            &PartialResult {
                format: SHARD_FORMAT.into(),
                shard,
                setup: CampaignSetup::of(&config),
                wall_time_s,
                results,
            },
        )?;
        println!(
            "shard {shard}: runs {}..{} of {} ({} converged), wall time {wall_time_s:.1} s; \
             wrote {} (combine the shards with `host-sim campaign merge`)",
            indices.start,
            indices.end,
            config.runs,
            converged,
            path.display()
        );
        return Ok(());
    }
    let bounds = bound_set(&config.scenario)?;
    let results = run_campaign_runs_within(&config, 0..config.runs, bounds)?;
    let wall = start.elapsed().as_secs_f64();
    let timing = format!(
        "wall time {wall:.1} s ({:.1} runs/s)",
        config.runs as f64 / wall.max(f64::MIN_POSITIVE)
    );
    finish(&config, bounds, &results, &args.out, args.plots, &timing)
}

/// `host-sim campaign merge`: combines the shards in `dirs` ([`merge_dirs`]) and writes the
/// files a single run of the campaign would write into `out`.
///
/// Errors: as [`merge_dirs`]; the bounds cannot be computed; a file cannot be written.
pub fn merge_command(dirs: &[PathBuf], out: &Path, plots: bool) -> Result<()> {
    let merged = merge_dirs(dirs)?;
    let timing = format!(
        "{} shards, {:.1} s of wall time in all",
        merged.shards, merged.wall_time_s
    );
    let config = merged.setup.config();
    let bounds = bound_set(&config.scenario)?;
    finish(&config, bounds, &merged.results, out, plots, &timing)
}

/// Summarises the runs of the whole campaign, writes its files and prints the summary.
fn finish(
    config: &CampaignConfig,
    bounds: BoundSet,
    results: &[RunResult],
    out: &Path,
    plots: bool,
    timing: &str,
) -> Result<()> {
    let nominal = !config.scenario.perturbations.violates_model();
    let stats = summarise(results, nominal);
    let report = CampaignReport::new(config, bounds, stats);
    let files = write_campaign(out, &report, results, plots)?;
    let r = &report.results;
    let checked = if nominal { &r.nominal } else { &r.perturbed };
    println!(
        "{} runs of {} s ({}): {} converged ({:.2} %), 180-deg starts {}/{}; settling p50 {} s, \
         p99 {} s; samples outside the a-priori bounds: {} of {} ({}), above the tight bounds: {}; \
         max switches in 1 s: {}; {timing}",
        r.runs,
        report.duration_s,
        if config.scenario.controller.is_paper() {
            report.controller.clone()
        } else {
            format!(
                "{}, thrust = {}",
                report.controller,
                config.scenario.controller.thrust.name()
            )
        },
        r.converged,
        100.0 * r.fraction_converged,
        r.half_turn_converged,
        r.half_turn_runs,
        fmt_opt(r.settling_time_s.p50),
        fmt_opt(r.settling_time_s.p99),
        checked.samples_outside_a_priori,
        checked.samples,
        if nominal {
            "nominal runs"
        } else {
            "perturbed runs"
        },
        checked.samples_above_tight,
        r.switching.max_switches_in_1s,
    );
    if let Some(m) = &r.mixer {
        let m = if nominal { &m.nominal } else { &m.perturbed };
        println!(
            "{} plant: the mixer gave something up in {} of {} samples (at most {:.3} N of \
             thrust, {:.4} N m of torque in one sample)",
            report.plant.name(),
            m.samples_given_up,
            m.samples,
            m.thrust_given_up_max_N,
            m.torque_given_up_max_Nm
        );
    }
    println!("Wrote {} files to {}", files.len(), out.display());
    Ok(())
}
