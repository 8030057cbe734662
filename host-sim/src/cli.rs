//! Command-line interface (clap).

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};

use crate::scenario::Precision;

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
    Sil(SilArgs),
    /// Processor in the loop: the firmware (Cortex-M4F build) in QEMU `mps2-an386` flies the
    /// SIL paper scenario over its emulated serial port, in lockstep; writes timeseries.csv,
    /// summary.json, defmt.bin and defmt.log.
    Pil(PilArgs),
    /// Robustness campaign: N runs from sampled initial conditions (Haar attitudes and 180°
    /// starts), in parallel; writes campaign.json, runs.csv and plots.
    Campaign(crate::experiments::CampaignArgs),
    /// Ablations of the paper's design choices: hysteresis vs memoryless lifting under noise at
    /// 180°, filtered vs unfiltered outer loop; writes ablation.md, ablation.json and plots.
    Ablation(crate::experiments::AblationArgs),
    /// The paper's law against the baselines (Lee et al. 2010, PX4-style cascade) on the same
    /// runs; writes compare.md (tables, embedded plots) and compare.json.
    Compare(crate::experiments::CompareArgs),
}

/// Options of a single run.
#[derive(Debug, Args, Clone, Default)]
pub struct RunArgs {
    /// Scenario file (TOML). Default: the embedded paper scenario (see `print-scenario`).
    #[arg(long, value_name = "FILE")]
    pub scenario: Option<PathBuf>,
    /// Output directory. Default: `./out/<scenario name>` ("paper" for the embedded scenario,
    /// the file stem otherwise). Created if missing; files in it are overwritten.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Controller precision, overriding the scenario's `simulation.precision`.
    #[arg(long, value_enum)]
    pub precision: Option<Precision>,
    /// Clip thrust and torque to the physical limits before applying them to the plant,
    /// overriding the scenario's `simulation.clip_to_limits`.
    #[arg(long)]
    pub clip: bool,
    /// Write only summary.json and the CSV (skip the PNG plots).
    #[arg(long)]
    pub no_plots: bool,
}

/// Options of a software-in-the-loop run.
#[derive(Debug, Args, Clone)]
pub struct SilArgs {
    /// Scenario: `paper` (the helix from the upside-down start), `pose-loss` (failsafe),
    /// `takeoff-land`.
    #[arg(long, default_value = "paper")]
    pub scenario: String,
    /// Random seed (sensor noise, dropouts, byte chunking).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Output directory. Default: `./out/sil-<scenario>`. Gets timeseries.csv and summary.json.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

/// Options of a processor-in-the-loop run (the SIL `paper` scenario on the firmware in QEMU).
#[derive(Debug, Args, Clone)]
pub struct PilArgs {
    /// Firmware ELF for QEMU `mps2-an386`. Default:
    /// `$CARGO_TARGET_DIR` (or `<workspace>/target`) + `/thumbv7em-none-eabihf/release/firmware-mps2-an386`.
    #[arg(long, value_name = "PATH")]
    pub elf: Option<PathBuf>,
    /// QEMU binary.
    #[arg(long, value_name = "BIN", default_value = "qemu-system-arm")]
    pub qemu: PathBuf,
    /// Output directory. Default: `./out/pil`. Gets timeseries.csv, summary.json, defmt.bin
    /// and defmt.log.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Random seed (sensor noise, dropouts, byte chunking).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Flight time after release, in seconds. Default: the scenario's 30 s.
    #[arg(long, value_name = "S")]
    pub duration: Option<f64>,
    /// Stall timeout: wall-clock seconds to wait for the firmware's answer to a tick.
    #[arg(long, value_name = "S", default_value_t = crate::pil::DEFAULT_TIMEOUT_S)]
    pub timeout: f64,
}
