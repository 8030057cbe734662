//! A campaign split into shards and merged writes the same bytes as the campaign run whole, and
//! the merge refuses shards that do not make up one campaign. Runs the `host-sim` binary, so
//! the command line (`--shard K/N`, `campaign merge DIR...`) is what is tested.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A short perturbed campaign (noise and mass error exercise each run's own noise stream):
/// 11 runs of 3 s, the seven 180° starts first.
const CAMPAIGN: &[&str] = &[
    "campaign",
    "--duration-s",
    "3",
    "--converged-after-s",
    "2",
    "--no-plots",
    "--threads",
    "2",
];

fn host_sim(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_host-sim"))
        .args(args)
        .output()
        .expect("host-sim starts")
}

fn ok(args: &[&str]) {
    let out = host_sim(args);
    assert!(
        out.status.success(),
        "host-sim {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The campaign of `runs` runs from `seed` (11 and 5 unless said otherwise).
fn campaign_of(scenario: &Path, (runs, seed): (&str, &str), extra: &[&str], out: &Path) {
    let mut args = CAMPAIGN.to_vec();
    args.extend(["--runs", runs, "--seed", seed]);
    let scenario = scenario.to_str().unwrap();
    let out = out.to_str().unwrap();
    args.extend(["--scenario", scenario, "--out", out]);
    args.extend(extra);
    ok(&args);
}

fn campaign(scenario: &Path, extra: &[&str], out: &Path) {
    campaign_of(scenario, ("11", "5"), extra, out);
}

fn merge(dirs: &[PathBuf], out: &Path) -> Output {
    let mut args = vec![
        "campaign",
        "merge",
        "--no-plots",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend(dirs.iter().map(|d| d.to_str().unwrap()));
    host_sim(&args)
}

/// The paper scenario with gyro noise and a mass error, written to `dir`.
fn perturbed_scenario(dir: &Path) -> PathBuf {
    let text = host_sim(&["print-scenario"]).stdout;
    let text = String::from_utf8(text).unwrap();
    let perturbed = format!(
        "{text}\n[perturbations]\ngyro_noise_std_rad_s = 0.02\nmass_error_max_fraction = 0.1\n"
    );
    let path = dir.join("scenario.toml");
    std::fs::write(&path, perturbed).unwrap();
    path
}

#[test]
fn three_shards_merged_give_the_bytes_of_one_run_and_bad_sets_are_refused() {
    let root = std::env::temp_dir().join(format!("host-sim-shards-{}", std::process::id()));
    std::fs::create_dir_all(&root).unwrap();
    let scenario = perturbed_scenario(&root);

    let whole = root.join("whole");
    campaign(&scenario, &[], &whole);
    let shards: Vec<PathBuf> = (0..3).map(|k| root.join(format!("shard-{k}"))).collect();
    for (k, dir) in shards.iter().enumerate() {
        campaign(&scenario, &["--shard", &format!("{k}/3")], dir);
        assert!(dir.join("shard.json").exists());
        assert!(
            !dir.join("campaign.json").exists(),
            "a shard is not a campaign"
        );
    }
    // Given in another order than the shards' numbers.
    let merged = root.join("merged");
    let reordered = [shards[2].clone(), shards[0].clone(), shards[1].clone()];
    let out = merge(&reordered, &merged);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for file in ["campaign.json", "runs.csv"] {
        let a = std::fs::read(whole.join(file)).unwrap();
        let b = std::fs::read(merged.join(file)).unwrap();
        assert!(a == b, "{file} differs between the whole run and the merge");
    }
    let csv = std::fs::read_to_string(merged.join("runs.csv")).unwrap();
    assert_eq!(csv.lines().count(), 12);

    let refused = |dirs: &[PathBuf], expected: &str| {
        let out = merge(dirs, &root.join("refused"));
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && err.contains(expected),
            "{expected}: {err}"
        );
    };
    refused(&shards[..2], "shards missing: 2/3 (runs 7..11)");
    refused(
        &[
            shards[0].clone(),
            shards[1].clone(),
            shards[1].clone(),
            shards[2].clone(),
        ],
        "shard 1/3 given twice",
    );
    let other_seed = root.join("other-seed");
    campaign_of(&scenario, ("11", "6"), &["--shard", "2/3"], &other_seed);
    refused(
        &[shards[0].clone(), shards[1].clone(), other_seed],
        "different seeds (5 vs 6)",
    );
    let other_runs = root.join("other-runs");
    campaign_of(&scenario, ("12", "5"), &["--shard", "2/3"], &other_runs);
    refused(
        &[shards[0].clone(), shards[1].clone(), other_runs],
        "different run counts (11 vs 12)",
    );
    let other_config = root.join("other-config");
    campaign(&scenario, &["--shard", "2/3", "--clip"], &other_config);
    refused(
        &[shards[0].clone(), shards[1].clone(), other_config],
        "different configurations (scenario tables that differ: [simulation])",
    );
    let other_split = root.join("other-split");
    campaign(&scenario, &["--shard", "1/2"], &other_split);
    refused(&[shards[0].clone(), other_split], "from one split");
    refused(&[root.join("nowhere")], "nowhere");

    let bad = host_sim(&["campaign", "--shard", "3/3"]);
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("K is 0-based"));
    std::fs::remove_dir_all(&root).unwrap();
}
