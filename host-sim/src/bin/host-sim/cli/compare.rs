//! `host-sim compare`: the paper's law against the baselines.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use host_sim::studies::compare::{self, CompareOptions};

use super::common::BaseArgs;

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

/// Runs the comparison ([`compare::run_command`]).
pub fn run(args: &CompareArgs) -> Result<()> {
    compare::run_command(&CompareOptions {
        out: args.out.clone(),
        runs: args.runs,
        base: (&args.base).into(),
    })
}
