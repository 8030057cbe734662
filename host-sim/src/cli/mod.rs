//! The command line of `host-sim` (clap): one file per subcommand, each owning its clap types
//! and turning them into the library's plain options. A module of the binary: the library
//! (`host_sim`) knows nothing of it.
//!
//! [`run`] is the default (one scenario), `print-scenario` is handled here, [`sil`], [`pil`],
//! [`campaign`], [`ablation`] and [`compare`] are the others.

mod ablation;
mod campaign;
mod compare;
mod pil;
mod run;
mod sil;

use std::path::PathBuf;

use anyhow::Result;
use clap::{Args, Parser, Subcommand, ValueEnum};
use host_sim::campaign::BaseOptions;
use host_sim::scenario::{Precision, PAPER_SCENARIO};

pub use run::RunArgs;

/// Simulate the saturated hybrid SE(3) tracking controller (controller-core) on a rigid-body
/// quadrotor model. With no arguments, runs the paper's Section VI scenario (embedded) and writes
/// its time series, plots and summary to ./out/paper.
#[derive(Debug, Parser)]
#[command(name = "host-sim", version, about, long_about = None)]
pub struct Cli {
    /// Run options (used when no subcommand is given).
    #[command(flatten)]
    pub run: RunArgs,
    /// Optional subcommand.
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// Subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run one scenario (the default when no subcommand is given).
    Run(RunArgs),
    /// Print the embedded paper scenario as TOML (a starting point for your own scenario files).
    PrintScenario,
    /// Software in the loop: the firmware's flight pipeline against the plant with simulated
    /// IMU, motion capture over MAVLink and motors.
    Sil(sil::SilArgs),
    /// Processor in the loop: the firmware (Cortex-M4F build) in QEMU `mps2-an386` flies the
    /// SIL paper scenario over its emulated serial port, in lockstep; writes timeseries.csv,
    /// summary.json, defmt.bin and defmt.log.
    Pil(pil::PilArgs),
    /// Robustness campaign: N runs from sampled initial conditions (Haar attitudes and 180°
    /// starts), in parallel; writes campaign.json, runs.csv and plots.
    Campaign(campaign::CampaignArgs),
    /// Ablations of the paper's design choices: hysteresis vs memoryless lifting under noise at
    /// 180°, filtered vs unfiltered outer loop; writes ablation.md, ablation.json and plots.
    Ablation(ablation::AblationArgs),
    /// The paper's law against the baselines (Lee et al. 2010, PX4-style cascade) on the same
    /// runs; writes compare.md (tables, embedded plots) and compare.json.
    Compare(compare::CompareArgs),
}

impl Cli {
    /// Runs the command. Errors: the command's (printed by `main` before a non-zero exit).
    pub fn dispatch(self) -> Result<()> {
        match self.command {
            None => run::run(&self.run),
            Some(Command::Run(args)) => run::run(&args),
            Some(Command::PrintScenario) => {
                print!("{PAPER_SCENARIO}");
                Ok(())
            }
            Some(Command::Sil(args)) => sil::run(&args),
            Some(Command::Pil(args)) => pil::run(&args),
            Some(Command::Campaign(args)) => campaign::run(&args),
            Some(Command::Ablation(args)) => ablation::run(&args),
            Some(Command::Compare(args)) => compare::run(&args),
        }
    }
}

/// Controller scalar type (the command line's spelling of [`Precision`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum PrecisionArg {
    /// Single precision, as on the flight controller.
    F32,
    /// Double precision.
    F64,
}

impl From<PrecisionArg> for Precision {
    fn from(p: PrecisionArg) -> Self {
        match p {
            PrecisionArg::F32 => Precision::F32,
            PrecisionArg::F64 => Precision::F64,
        }
    }
}

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
    pub precision: Option<PrecisionArg>,
}

impl From<&BaseArgs> for BaseOptions {
    fn from(a: &BaseArgs) -> Self {
        Self {
            scenario: a.scenario.clone(),
            seed: a.seed,
            duration_s: a.duration_s,
            controller_rate_hz: a.controller_rate_hz,
            clip: a.clip,
            precision: a.precision.map(Precision::from),
        }
    }
}
