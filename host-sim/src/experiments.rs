//! The `campaign`, `ablation` and `compare` subcommands: their options and entry points.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{bail, Result};
use clap::Args;

use crate::campaign::output::{write_campaign, CampaignReport};
use crate::campaign::runner::bound_set;
use crate::campaign::{run_campaign, summarise, CampaignConfig, Convergence, SamplerRadii};
use crate::controllers::ControllerKind;
use crate::scenario::{Precision, Scenario};

/// Options shared by the three commands: the base scenario and the seed.
#[derive(Debug, Args, Clone)]
pub struct BaseArgs {
    /// Base scenario file (TOML). Default: the embedded paper scenario. Its `[initial]` table is
    /// replaced by the sampled initial conditions; its `[perturbations]` apply to every run.
    #[arg(long, value_name = "FILE")]
    pub scenario: Option<PathBuf>,
    /// Campaign seed: run i draws from splitmix(seed, i), so results do not depend on threads.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Simulated duration of every run \[s\], overriding `simulation.duration_s`.
    #[arg(long, value_name = "S")]
    pub duration_s: Option<f64>,
    /// Controller rate \[Hz\], overriding `simulation.controller_period_s`.
    #[arg(long, value_name = "HZ")]
    pub controller_rate_hz: Option<f64>,
    /// Clip thrust and torque to the physical limits before the plant.
    #[arg(long)]
    pub clip: bool,
    /// Controller precision for the paper's law, overriding `simulation.precision`.
    #[arg(long, value_enum)]
    pub precision: Option<Precision>,
}

impl BaseArgs {
    /// The scenario with the overrides applied.
    ///
    /// Errors: the file cannot be read or is invalid; an override is not finite and > 0.
    pub fn scenario(&self) -> Result<Scenario> {
        let mut s = match &self.scenario {
            Some(p) => Scenario::load(p)?,
            None => Scenario::paper(),
        };
        if let Some(d) = self.duration_s {
            if !(d.is_finite() && d > 0.0) {
                bail!("--duration-s must be finite and > 0, got {d}");
            }
            s.simulation.duration_s = d;
        }
        if let Some(hz) = self.controller_rate_hz {
            if !(hz.is_finite() && hz > 0.0) {
                bail!("--controller-rate-hz must be finite and > 0, got {hz}");
            }
            s.simulation.controller_period_s = 1.0 / hz;
            s.simulation.plant_step_s = s.simulation.plant_step_s.min(1.0 / hz);
        }
        s.simulation.clip_to_limits |= self.clip;
        if let Some(p) = self.precision {
            s.simulation.precision = p;
        }
        s.validate().map_err(|e| anyhow::anyhow!("{e}"))?;
        Ok(s)
    }
}

/// Options of `host-sim campaign`.
#[derive(Debug, Args, Clone)]
pub struct CampaignArgs {
    /// Number of runs.
    #[arg(long, default_value_t = 1000)]
    pub runs: u64,
    /// Output directory (created; files overwritten).
    #[arg(long, value_name = "DIR", default_value = "out/campaign")]
    pub out: PathBuf,
    /// Controller flown in every run.
    #[arg(long, value_enum, default_value_t = ControllerKind::Paper)]
    pub controller: ControllerKind,
    /// Scenario, seed and overrides.
    #[command(flatten)]
    pub base: BaseArgs,
    /// Radius of the position-offset ball around p_d(0) \[m\].
    #[arg(long, default_value_t = SamplerRadii::default().position_m)]
    pub position_radius_m: f64,
    /// Radius of the velocity-offset ball around the reference velocity [m/s].
    #[arg(long, default_value_t = SamplerRadii::default().velocity_m_s)]
    pub velocity_radius_m_s: f64,
    /// Radius of the body angular-velocity ball [rad/s].
    #[arg(long, default_value_t = SamplerRadii::default().angular_velocity_rad_s)]
    pub angular_velocity_radius_rad_s: f64,
    /// Leave out the fixed 180° starts (all runs Haar-uniform).
    #[arg(long)]
    pub no_half_turns: bool,
    /// Convergence: position error threshold \[m\].
    #[arg(long, default_value_t = Convergence::default().position_m)]
    pub converged_position_m: f64,
    /// Convergence: attitude error threshold \[deg\].
    #[arg(long, default_value_t = Convergence::default().attitude_deg)]
    pub converged_attitude_deg: f64,
    /// Convergence: settled by this time \[s\].
    #[arg(long, default_value_t = Convergence::default().after_s)]
    pub converged_after_s: f64,
    /// Write only campaign.json and runs.csv.
    #[arg(long)]
    pub no_plots: bool,
    /// Worker threads (default: one per core); the results do not depend on it.
    #[arg(long)]
    pub threads: Option<usize>,
}

/// `host-sim campaign`: runs the campaign, prints a short summary, writes the files.
///
/// Errors: invalid options or scenario; a file cannot be written.
pub fn campaign(args: &CampaignArgs) -> Result<()> {
    let scenario = args.base.scenario()?;
    if args.converged_after_s > scenario.simulation.duration_s {
        bail!(
            "--converged-after-s ({}) is after the end of the run ({} s)",
            args.converged_after_s,
            scenario.simulation.duration_s
        );
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
        half_turns: !args.no_half_turns,
        convergence: Convergence {
            position_m: args.converged_position_m,
            attitude_deg: args.converged_attitude_deg,
            after_s: args.converged_after_s,
        },
        progress: true,
        threads: args.threads,
    };
    let start = Instant::now();
    let results = run_campaign(&config)?;
    let wall = start.elapsed().as_secs_f64();
    let nominal = !config.scenario.perturbations.violates_model();
    let stats = summarise(&results, nominal);
    let report = CampaignReport::new(&config, bound_set(&config.scenario)?, stats, wall);
    let files = write_campaign(&args.out, &report, &results, !args.no_plots)?;
    let r = &report.results;
    let checked = if nominal { &r.nominal } else { &r.perturbed };
    println!(
        "{} runs of {} s ({}): {} converged ({:.2} %), 180-deg starts {}/{}; settling p50 {} s, \
         p99 {} s; samples outside the a-priori bounds: {} of {} ({}); max switches in 1 s: {}; \
         wall time {:.1} s ({:.1} runs/s)",
        r.runs,
        report.duration_s,
        report.controller,
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
        r.switching.max_switches_in_1s,
        wall,
        report.runs_per_s
    );
    println!("Wrote {} files to {}", files.len(), args.out.display());
    Ok(())
}

/// `x.xx` or `-`.
pub fn fmt_opt(x: Option<f64>) -> String {
    x.map_or_else(|| "-".into(), |v| format!("{v:.2}"))
}

/// Options of `host-sim ablation`.
#[derive(Debug, Args, Clone)]
pub struct AblationArgs {
    /// Output directory.
    #[arg(long, value_name = "DIR", default_value = "out/ablation")]
    pub out: PathBuf,
    /// Repetitions of the seven 180° starts per noise level (hysteresis ablation).
    #[arg(long, default_value_t = 4)]
    pub repeats: u64,
    /// Scenario, seed and overrides.
    #[command(flatten)]
    pub base: BaseArgs,
}

/// Options of `host-sim compare`.
#[derive(Debug, Args, Clone)]
pub struct CompareArgs {
    /// Output directory.
    #[arg(long, value_name = "DIR", default_value = "out/compare")]
    pub out: PathBuf,
    /// Runs of the campaign each controller flies (the same initial conditions for all).
    #[arg(long, default_value_t = 200)]
    pub runs: u64,
    /// Scenario, seed and overrides.
    #[command(flatten)]
    pub base: BaseArgs,
}
