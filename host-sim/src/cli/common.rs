//! Clap types shared by several subcommands: the precision, and the base scenario options of
//! `campaign`, `ablation` and `compare`.

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use host_sim::campaign::BaseOptions;
use host_sim::scenario::Precision;

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
    /// Simulated duration of every run (s), overriding `simulation.duration_s`.
    #[arg(long, value_name = "S")]
    pub duration_s: Option<f64>,
    /// Controller rate (Hz), overriding `simulation.controller_period_s`.
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Every spelling on the command line names the precision of the same scenario-file name.
    #[test]
    fn precision_spellings_map_to_their_precisions() {
        for v in PrecisionArg::value_variants() {
            let name = v.to_possible_value().map(|p| p.get_name().to_string());
            let serde_name = serde_json::to_string(&Precision::from(*v)).ok();
            assert_eq!(name.map(|n| format!("\"{n}\"")), serde_name);
        }
    }
}
