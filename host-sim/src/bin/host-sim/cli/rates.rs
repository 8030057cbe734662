//! `host-sim rates`: the law at 100, 250, 500 and 1 000 Hz compared, in SIL and in a campaign
//! on the rotor plant with motor lag.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use host_sim::studies::rates::{self, CampaignPlan, RateStudyOptions};

/// Options of the rate study.
#[derive(Debug, Args, Clone)]
pub struct RatesArgs {
    /// Output directory (created; rates.md and rates.json overwritten).
    #[arg(long, value_name = "DIR", default_value = "out/rates")]
    pub out: PathBuf,
    /// Seed of the SIL runs (sensor noise, dropouts, byte chunking).
    #[arg(long, default_value_t = 1)]
    pub sil_seed: u64,
    /// Campaign runs per rate (0: SIL only).
    #[arg(long, default_value_t = 200)]
    pub runs: u64,
    /// Campaign seed (the same initial conditions at every rate).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Vehicle file of the campaign's rotor plant (rotors, motor time constant). Default: the
    /// paper's vehicle on rotors, host-sim/vehicles/paper.toml.
    #[arg(long, value_name = "FILE")]
    pub vehicle: Option<PathBuf>,
    /// Motor time constant [s] of the campaign's rotors, replacing the vehicle's.
    #[arg(long, value_name = "S")]
    pub motor_time_constant_s: Option<f64>,
    /// Campaign worker threads (default: one per core); the results do not depend on it.
    #[arg(long)]
    pub threads: Option<usize>,
}

/// Runs the study ([`rate_study::run_command`]).
pub fn run(args: &RatesArgs) -> Result<()> {
    let vehicle = args.vehicle.clone().unwrap_or_else(|| {
        PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/vehicles/paper.toml"))
    });
    rates::run_command(&RateStudyOptions {
        out: args.out.clone(),
        sil_seed: args.sil_seed,
        campaign: (args.runs > 0).then_some(CampaignPlan {
            runs: args.runs,
            seed: args.seed,
            vehicle,
            motor_time_constant_s: args.motor_time_constant_s,
            threads: args.threads,
        }),
    })
}
