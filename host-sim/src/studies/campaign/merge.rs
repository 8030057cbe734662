//! Combines the partial results of `campaign --shard K/N` into the whole campaign's results,
//! refusing shards that do not make up exactly one campaign: other set-ups (seed, run count,
//! controller, scenario, ...), another split, a shard given twice, a shard missing, or a shard
//! whose runs are not its share.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{bail, Result};

use super::partial::{CampaignSetup, PartialResult};
use super::shard::Shard;
use crate::runs::runner::RunResult;
use crate::runs::sampler::run_seed;

/// The merged campaign.
#[derive(Clone, Debug)]
pub struct Merged {
    /// The campaign's set-up (that of every shard).
    pub setup: CampaignSetup,
    /// All runs, in run order.
    pub results: Vec<RunResult>,
    /// Sum of the shards' wall times \[s\].
    pub wall_time_s: f64,
    /// Number of shards.
    pub shards: u64,
}

/// Merges the shards (each with the directory it was read from, for the error messages).
///
/// Errors: no shard; the shards' set-ups or splits differ (the first difference is named);
/// a shard is given twice or missing; a shard's runs are not its share of the run indices.
pub fn merge_partials(parts: Vec<(PathBuf, PartialResult)>) -> Result<Merged> {
    let Some((first_dir, first)) = parts.first() else {
        bail!("no shard directories given");
    };
    let (first_dir, setup, first_shard) = (first_dir.clone(), first.setup.clone(), first.shard);
    let count = first_shard.count;
    let mut by_index: BTreeMap<u64, (PathBuf, PartialResult)> = BTreeMap::new();
    let mut wall_time_s = 0.0;
    for (dir, part) in parts {
        if let Some(what) = setup_difference(&setup, &part.setup) {
            bail!(
                "{} and {} are shards of different campaigns: {what}",
                first_dir.display(),
                dir.display()
            );
        }
        if part.shard.count != count {
            bail!(
                "{} is shard {} but {} is shard {}: all shards must come from one split into \
                 the same number of shards",
                first_dir.display(),
                first_shard,
                dir.display(),
                part.shard
            );
        }
        check_share(&dir, &part)?;
        wall_time_s += part.wall_time_s;
        if let Some((other, _)) = by_index.get(&part.shard.index) {
            bail!(
                "shard {} given twice: {} and {}",
                part.shard,
                other.display(),
                dir.display()
            );
        }
        by_index.insert(part.shard.index, (dir, part));
    }
    let missing: Vec<String> = (0..count)
        .filter(|k| !by_index.contains_key(k))
        .map(|k| {
            let r = Shard { index: k, count }.runs(setup.runs);
            format!("{k}/{count} (runs {}..{})", r.start, r.end)
        })
        .collect();
    if !missing.is_empty() {
        bail!("shards missing: {}", missing.join(", "));
    }
    let results = by_index
        .into_values()
        .flat_map(|(_, part)| part.results)
        .collect();
    Ok(Merged {
        setup,
        results,
        wall_time_s,
        shards: count,
    })
}

/// Reads `dir/shard.json` of every directory and merges them ([`merge_partials`]).
///
/// Errors: a shard file cannot be read ([`super::partial::read_partial`]); as
/// [`merge_partials`].
pub fn merge_dirs(dirs: &[PathBuf]) -> Result<Merged> {
    let parts = dirs
        .iter()
        .map(|d| Ok((d.clone(), super::partial::read_partial(d)?)))
        .collect::<Result<Vec<_>>>()?;
    merge_partials(parts)
}

/// A shard holds exactly its share of the runs, in order, each with its own seed.
fn check_share(dir: &Path, part: &PartialResult) -> Result<()> {
    let expected = part.shard.runs(part.setup.runs);
    let indices_match = part.results.len() as u64 == expected.end - expected.start
        && part
            .results
            .iter()
            .zip(expected.clone())
            .all(|(r, i)| r.index == i && r.seed == run_seed(part.setup.seed, i));
    if !indices_match {
        bail!(
            "{} is shard {} of {} runs, which should hold runs {}..{} with their seeds, but \
             holds {} results: the file was altered or is damaged",
            dir.display(),
            part.shard,
            part.setup.runs,
            expected.start,
            expected.end,
            part.results.len()
        );
    }
    Ok(())
}

/// The first difference between two set-ups, in words; `None` when they are equal.
pub fn setup_difference(a: &CampaignSetup, b: &CampaignSetup) -> Option<String> {
    if a == b {
        return None;
    }
    let named = |what: &str, x: String, y: String| Some(format!("different {what} ({x} vs {y})"));
    if a.seed != b.seed {
        return named("seeds", a.seed.to_string(), b.seed.to_string());
    }
    if a.runs != b.runs {
        return named("run counts", a.runs.to_string(), b.runs.to_string());
    }
    if a.controller != b.controller {
        return named(
            "controllers",
            a.controller.label().into(),
            b.controller.label().into(),
        );
    }
    if a.radii != b.radii {
        return named(
            "sampler radii",
            format!("{:?}", a.radii),
            format!("{:?}", b.radii),
        );
    }
    if a.half_turns != b.half_turns {
        return named(
            "180° starts",
            a.half_turns.to_string(),
            b.half_turns.to_string(),
        );
    }
    if a.convergence != b.convergence {
        return named(
            "convergence thresholds",
            format!("{:?}", a.convergence),
            format!("{:?}", b.convergence),
        );
    }
    Some(format!(
        "different configurations (scenario tables that differ: {})",
        scenario_tables_differing(&a.scenario, &b.scenario)
    ))
}

/// The scenario's top-level tables (`[simulation]`, `[perturbations]`, ...) that differ.
fn scenario_tables_differing(
    a: &crate::model::scenario::Scenario,
    b: &crate::model::scenario::Scenario,
) -> String {
    let (Ok(serde_json::Value::Object(a)), Ok(serde_json::Value::Object(b))) =
        (serde_json::to_value(a), serde_json::to_value(b))
    else {
        return "unknown".into();
    };
    let mut keys: Vec<&String> = a.keys().chain(b.keys()).collect();
    keys.sort();
    keys.dedup();
    let differing: Vec<String> = keys
        .into_iter()
        .filter(|k| a.get(*k) != b.get(*k))
        .map(|k| format!("[{k}]"))
        .collect();
    if differing.is_empty() {
        // Equal as JSON but not as values: a difference below JSON's float precision.
        "values that print alike".into()
    } else {
        differing.join(", ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fly::controllers::ControllerKind;
    use crate::model::scenario::Scenario;
    use crate::runs::metrics::Convergence;
    use crate::runs::sampler::SamplerRadii;

    fn setup(runs: u64) -> CampaignSetup {
        CampaignSetup {
            controller: ControllerKind::Paper,
            runs,
            seed: 7,
            radii: SamplerRadii::default(),
            half_turns: true,
            convergence: Convergence::default(),
            scenario: Scenario::paper(),
        }
    }

    /// A shard of `runs` runs with placeholder results (no metrics) at the right indices.
    fn part(setup: &CampaignSetup, index: u64, count: u64) -> (PathBuf, PartialResult) {
        let shard = Shard::new(index, count).unwrap();
        let results = shard
            .runs(setup.runs)
            .map(|i| RunResult {
                index: i,
                seed: run_seed(setup.seed, i),
                start: "haar".into(),
                initial_attitude_error_deg: i as f64,
                initial_position_error_m: 0.0,
                metrics: None,
                error: None,
            })
            .collect();
        (
            PathBuf::from(format!("s{index}")),
            PartialResult {
                format: crate::studies::campaign::partial::SHARD_FORMAT.into(),
                shard,
                setup: setup.clone(),
                wall_time_s: 1.0,
                results,
            },
        )
    }

    fn error_of(parts: Vec<(PathBuf, PartialResult)>) -> String {
        format!("{:#}", merge_partials(parts).unwrap_err())
    }

    #[test]
    fn merges_shards_given_in_any_order_into_run_order() {
        let s = setup(10);
        let m = merge_partials(vec![part(&s, 2, 3), part(&s, 0, 3), part(&s, 1, 3)]).unwrap();
        let indices: Vec<u64> = m.results.iter().map(|r| r.index).collect();
        assert_eq!(indices, (0..10).collect::<Vec<_>>());
        assert_eq!(m.shards, 3);
        assert_eq!(m.wall_time_s, 3.0);
    }

    #[test]
    fn refuses_overlapping_missing_and_mismatched_shards() {
        let s = setup(10);
        let e = error_of(vec![part(&s, 0, 3), part(&s, 1, 3), part(&s, 1, 3)]);
        assert!(e.contains("shard 1/3 given twice"), "{e}");
        let e = error_of(vec![part(&s, 0, 3), part(&s, 2, 3)]);
        assert!(e.contains("shards missing: 1/3 (runs 3..6)"), "{e}");
        let e = error_of(vec![part(&s, 0, 2), part(&s, 1, 3)]);
        assert!(e.contains("from one split"), "{e}");
        let e = error_of(vec![part(&s, 0, 2), part(&setup(11), 1, 2)]);
        assert!(e.contains("different run counts (10 vs 11)"), "{e}");
        let mut other = setup(10);
        other.seed = 8;
        let e = error_of(vec![part(&s, 0, 2), part(&other, 1, 2)]);
        assert!(e.contains("different seeds (7 vs 8)"), "{e}");
        let mut other = setup(10);
        other.scenario.simulation.duration_s = 5.0;
        let e = error_of(vec![part(&s, 0, 2), part(&other, 1, 2)]);
        assert!(e.contains("[simulation]"), "{e}");
        let mut damaged = part(&s, 1, 2);
        damaged.1.results.pop();
        let e = error_of(vec![part(&s, 0, 2), damaged]);
        assert!(e.contains("should hold runs 5..10"), "{e}");
        assert!(error_of(vec![]).contains("no shard"));
    }
}
