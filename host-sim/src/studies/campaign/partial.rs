//! A shard's partial result, `shard.json`: what `campaign --shard K/N` writes and
//! `campaign merge` reads. It holds the whole set-up (so the merge needs no scenario file and
//! can tell shards of different campaigns apart) and every run's full result (so the merge
//! computes the statistics from exactly the values a single process would have).
//!
//! Floats are written in shortest round-trip form and read back with `serde_json`'s
//! `float_roundtrip` parser; [`write_partial`] reads its own file back and refuses to leave one
//! that does not reproduce the results bit for bit (JSON has no NaN or infinity).

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use serde::{Deserialize, Serialize};

use super::shard::Shard;
use crate::fly::controllers::ControllerKind;
use crate::model::scenario::Scenario;
use crate::runs::metrics::Convergence;
use crate::runs::runner::{CampaignConfig, RunResult};
use crate::runs::sampler::SamplerRadii;

/// Name of a shard's file in its output directory.
pub const SHARD_FILE: &str = "shard.json";

/// The format tag of [`PartialResult::format`]; changed whenever the file's meaning changes.
pub const SHARD_FORMAT: &str = "host-sim campaign shard 1";

/// Everything a campaign's results depend on: two shards belong to one campaign exactly when
/// their set-ups are equal (the thread count and the progress bar change nothing).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CampaignSetup {
    /// Controller flown in every run.
    pub controller: ControllerKind,
    /// Runs of the whole campaign.
    pub runs: u64,
    /// Campaign seed.
    pub seed: u64,
    /// Offset ball radii.
    pub radii: SamplerRadii,
    /// The fixed 180° starts come first.
    pub half_turns: bool,
    /// Convergence thresholds.
    pub convergence: Convergence,
    /// The base scenario with every command-line override applied, written as its TOML text
    /// (serde_json cannot read the scenario's tagged tables back with the `arbitrary_precision`
    /// feature another dependency turns on; TOML floats round-trip exactly).
    #[serde(with = "scenario_toml")]
    pub scenario: Scenario,
}

/// [`Scenario`] as a string of TOML inside the JSON.
mod scenario_toml {
    use serde::{de::Error as _, ser::Error as _, Deserialize, Deserializer, Serializer};

    use crate::model::scenario::Scenario;

    pub fn serialize<S: Serializer>(scenario: &Scenario, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&toml::to_string(scenario).map_err(S::Error::custom)?)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Scenario, D::Error> {
        let text = String::deserialize(d)?;
        Scenario::parse(&text, "in shard.json").map_err(|e| D::Error::custom(format!("{e:#}")))
    }
}

impl CampaignSetup {
    /// The set-up of `config`.
    pub fn of(config: &CampaignConfig) -> Self {
        Self {
            controller: config.controller,
            runs: config.runs,
            seed: config.seed,
            radii: config.radii,
            half_turns: config.half_turns,
            convergence: config.convergence,
            scenario: config.scenario.clone(),
        }
    }

    /// The campaign configuration of this set-up (no progress bar, default threads).
    pub fn config(&self) -> CampaignConfig {
        CampaignConfig {
            scenario: self.scenario.clone(),
            controller: self.controller,
            runs: self.runs,
            seed: self.seed,
            radii: self.radii,
            half_turns: self.half_turns,
            convergence: self.convergence,
            progress: false,
            threads: None,
        }
    }
}

/// `shard.json`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PartialResult {
    /// [`SHARD_FORMAT`].
    pub format: String,
    /// Which share of the runs this is.
    pub shard: Shard,
    /// The campaign's set-up.
    pub setup: CampaignSetup,
    /// Wall time of this shard's runs \[s\] (information only: not in the merged files).
    pub wall_time_s: f64,
    /// The results of runs `shard.runs(setup.runs)`, in run order.
    pub results: Vec<RunResult>,
}

/// Writes `dir/shard.json` (`dir` created if missing) and returns its path.
///
/// Errors: the file cannot be written (named); a result does not survive the JSON round trip
/// (a non-finite metric), which would make the merge differ from a single run.
pub fn write_partial(dir: &Path, partial: &PartialResult) -> Result<PathBuf> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let path = dir.join(SHARD_FILE);
    let text = serde_json::to_string(partial)?;
    // Debug prints every float in full (shortest round trip), so equal text is equal bits.
    let back: Result<PartialResult, _> = serde_json::from_str(&text);
    if !back.is_ok_and(|b| format!("{b:?}") == format!("{partial:?}")) {
        bail!(
            "shard {} cannot be written losslessly to {} (a non-finite value in a run's \
             metrics?); run this campaign unsharded",
            partial.shard,
            path.display()
        );
    }
    std::fs::write(&path, text + "\n").with_context(|| format!("writing {}", path.display()))?;
    Ok(path)
}

/// Reads `dir/shard.json`.
///
/// Errors: the file is missing or unreadable, is not a shard file, or has another format.
pub fn read_partial(dir: &Path) -> Result<PartialResult> {
    let path = dir.join(SHARD_FILE);
    let text = std::fs::read_to_string(&path).with_context(|| {
        format!(
            "reading {} (the output of `host-sim campaign --shard K/N --out {}`)",
            path.display(),
            dir.display()
        )
    })?;
    #[derive(Deserialize)]
    struct Tag {
        format: Option<String>,
    }
    let tag: Tag = serde_json::from_str(&text)
        .with_context(|| format!("{} is not a campaign shard file", path.display()))?;
    if tag.format.as_deref() != Some(SHARD_FORMAT) {
        bail!(
            "{} has format {:?}, this host-sim reads {SHARD_FORMAT:?}: merge with the \
             host-sim that ran the shards",
            path.display(),
            tag.format.unwrap_or_default()
        );
    }
    serde_json::from_str(&text).with_context(|| format!("reading {}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A shard of a perturbed campaign survives the file bit for bit: its set-up compares
    /// equal and every float of every run prints alike (Debug: shortest round trip).
    #[test]
    fn a_shard_file_carries_its_runs_exactly() {
        let mut scenario = Scenario::paper();
        scenario.simulation.duration_s = 2.0;
        scenario.perturbations.gyro_noise_std_rad_s = 0.02;
        scenario.perturbations.mass_error_max_fraction = 0.1;
        let setup = CampaignSetup {
            controller: ControllerKind::Paper,
            runs: 9,
            seed: 3,
            radii: SamplerRadii::default(),
            half_turns: true,
            convergence: Convergence::default(),
            scenario,
        };
        let shard = Shard::new(1, 2).unwrap();
        let mut config = setup.config();
        config.threads = Some(1);
        let results = crate::runs::runner::run_campaign_runs(&config, shard.runs(9)).unwrap();
        assert_eq!(results.len(), 5);
        let partial = PartialResult {
            format: SHARD_FORMAT.into(),
            shard,
            setup,
            wall_time_s: 0.5,
            results,
        };
        let text = serde_json::to_string(&partial).unwrap();
        let back: PartialResult = serde_json::from_str(&text).unwrap();
        assert_eq!(back.setup, partial.setup);
        let (a, b) = (format!("{partial:?}"), format!("{back:?}"));
        let at = a.bytes().zip(b.bytes()).position(|(x, y)| x != y);
        assert!(
            at.is_none(),
            "the round trip changed {:?}",
            at.map(|i| &a[i..])
        );
    }
}
