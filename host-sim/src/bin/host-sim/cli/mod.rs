//! The command line of `host-sim` (clap): one file per subcommand, each owning its clap types
//! and turning them into the library's plain options. A module of the binary: the library
//! (`host_sim`) knows nothing of it.
//!
//! [`run`] is the default (one scenario), `print-scenario` is handled here, [`sil`], [`pil`],
//! [`campaign`], [`ablation`], [`compare`], [`design`], [`score`], [`bounds`] and [`rates`] are
//! the others; [`common`] holds the clap types
//! they share.

mod ablation;
mod bounds;
mod campaign;
mod common;
mod compare;
mod design;
mod pil;
mod rates;
mod run;
mod score;
mod sil;

use anyhow::Result;
use clap::{Parser, Subcommand};
use host_sim::model::scenario::PAPER_SCENARIO;

use run::RunArgs;

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
    /// Certified gains for a vehicle file: every condition of the paper holds, the certified
    /// (T, tau) set fits the rotors with a margin, best on a simulated objective; writes
    /// design.json, design.md, scenario.toml and firmware.toml.
    Design(design::DesignArgs),
    /// A scenario file (a design's scenario.toml, edited or not) judged as `design` judges its
    /// candidates: the certificate against its rotors (violated conditions by name, the fit's
    /// headroom) and the objective's runs (half turns, upside down, step, roll, disturbance).
    Score(score::ScoreArgs),
    /// The a-priori bounds of a set-up three ways: the paper's (Lemma 1, Theorem 2), the tight
    /// ones (supremum of the law over its confining set, interval branch and bound) and the
    /// largest value found at an admissible state; Theorem 2's torque conditions with both.
    Bounds(bounds::BoundsArgs),
    /// The control law at 100, 250, 500 and 1000 Hz compared: SIL scenarios and a campaign on
    /// the rotor plant with motor lag (tracking error, torque peaks, bound margins); writes
    /// rates.md and rates.json.
    Rates(rates::RatesArgs),
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
            Some(Command::Bounds(args)) => bounds::run(&args),
            Some(Command::Compare(args)) => compare::run(&args),
            Some(Command::Design(args)) => design::run(&args),
            Some(Command::Score(args)) => score::run(&args),
            Some(Command::Rates(args)) => rates::run(&args),
        }
    }
}

#[cfg(test)]
mod tests {
    use clap::CommandFactory;

    use super::*;

    /// clap's own consistency checks of every subcommand (names, defaults, conflicts).
    #[test]
    fn the_command_line_is_consistent() {
        Cli::command().debug_assert();
    }

    /// Given `score` with two `--set` edits and `--json`, when the command line is parsed, then
    /// the edits arrive in order with their paths and TOML values, and a malformed edit is
    /// refused by clap with the expected form.
    #[test]
    fn score_takes_key_edits() {
        let cli = Cli::try_parse_from([
            "host-sim",
            "score",
            "--scenario",
            "s.toml",
            "--set",
            "gains.local.kp=36",
            "--set",
            "gains.tilt_priority.omega_levels_Nm=[0.5, 0.5, 0.01]",
            "--json",
            "out.json",
        ])
        .unwrap();
        let Some(Command::Score(args)) = cli.command else {
            panic!("not score");
        };
        assert_eq!(args.set.len(), 2);
        assert_eq!(args.set[0].path, ["gains", "local", "kp"]);
        assert_eq!(args.set[0].value, toml::Value::Integer(36));
        assert_eq!(
            args.set[1].value.as_array().map(|a| a.len()),
            Some(3),
            "{:?}",
            args.set[1]
        );
        assert_eq!(args.json.as_deref(), Some(std::path::Path::new("out.json")));
        let run = Cli::try_parse_from(["host-sim", "--set", "gains.M_p=2"]).unwrap();
        assert_eq!(run.run.set[0].path, ["gains", "M_p"]);
        let bad = Cli::try_parse_from(["host-sim", "score", "--scenario", "s", "--set", "kp"]);
        let message = bad.err().map(|e| e.to_string()).unwrap_or_default();
        assert!(message.contains("TABLE.KEY=VALUE"), "{message}");
    }
}
