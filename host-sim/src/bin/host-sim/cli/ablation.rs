//! `host-sim ablation`: the paper's design choices, measured.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use host_sim::studies::ablation::{self, AblationOptions};

use super::common::BaseArgs;

/// Options of `host-sim ablation`.
#[derive(Debug, Args, Clone)]
pub struct AblationArgs {
    /// Output directory.
    #[arg(long, value_name = "DIR", default_value = "out/ablation")]
    pub out: PathBuf,
    /// Repetitions of the seven 180° starts per noise level (hysteresis ablation).
    #[arg(long, default_value_t = 4)]
    pub repeats: u64,
    /// Runs per cell of the integral action's table (each case with and without it).
    #[arg(long, default_value_t = host_sim::studies::ablation::integral::DEFAULT_RUNS)]
    pub integral_runs: u64,
    /// Runs per cell of its combined case (mass, inertia, force, gusts); default: --integral-runs.
    #[arg(long)]
    pub integral_combined_runs: Option<u64>,
    /// Scenario, seed and overrides.
    #[command(flatten)]
    pub base: BaseArgs,
}

/// Runs the ablations ([`ablation::run_command`]).
pub fn run(args: &AblationArgs) -> Result<()> {
    ablation::run_command(&AblationOptions {
        out: args.out.clone(),
        repeats: args.repeats,
        integral_runs: ablation::IntegralRuns {
            runs: args.integral_runs,
            combined: args.integral_combined_runs.unwrap_or(args.integral_runs),
        },
        base: (&args.base).into(),
    })
}
