//! The rotor plant from the command line: `--plant rotors` on the main run and on a campaign,
//! with the rotors of the scenario's `[rotors]` table or of `--vehicle FILE`; refused without
//! rotors.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use host_sim::model::scenario::PAPER_SCENARIO;
use host_sim::model::vehicle::preset_path;

fn host_sim(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_host-sim"))
        .args(args)
        .output()
        .expect("host-sim runs")
}

fn temp(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("host-sim-rotor-runs-{name}-{}", std::process::id()))
}

/// The paper scenario file with the `[rotors]` table of the paper vehicle file appended.
fn paper_with_rotors(dir: &Path) -> PathBuf {
    let vehicle = std::fs::read_to_string(preset_path("paper")).unwrap();
    // The table's header line (comments may name it too).
    let start = vehicle.find("\n[rotors]").expect("[rotors] in paper.toml");
    let rest = &vehicle[start + 1..];
    let end = rest[1..].find("\n[").map_or(rest.len(), |i| i + 1);
    std::fs::create_dir_all(dir).unwrap();
    let path = dir.join("paper-rotors.toml");
    std::fs::write(&path, format!("{PAPER_SCENARIO}\n{}\n", &rest[..end])).unwrap();
    path
}

fn csv_header(path: &Path) -> String {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .next()
        .unwrap()
        .to_string()
}

#[test]
fn main_run_on_the_rotor_plant_writes_rotor_columns() {
    let dir = temp("main");
    let scenario = paper_with_rotors(&dir);
    let scenario = scenario.to_str().unwrap();
    let run = |plant: &str, out: &Path| {
        let o = host_sim(&[
            "--scenario",
            scenario,
            "--plant",
            plant,
            "--no-plots",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    };
    let (ideal, rotors) = (dir.join("ideal"), dir.join("rotors"));
    run("ideal", &ideal);
    run("rotors", &rotors);
    let h_ideal = csv_header(&ideal.join("timeseries.csv"));
    let h_rotors = csv_header(&rotors.join("timeseries.csv"));
    assert!(!h_ideal.contains("rotor_1_thrust_N"), "{h_ideal}");
    assert!(h_rotors.starts_with(&h_ideal), "{h_rotors}");
    for column in [
        "rotor_1_thrust_N",
        "rotor_4_thrust_N",
        "mixer_thrust_given_up_N",
    ] {
        assert!(h_rotors.contains(column), "{h_rotors}");
    }
    let summary = std::fs::read_to_string(rotors.join("summary.json")).unwrap();
    assert!(summary.contains("\"samples_given_up\""), "{summary}");
    let summary = std::fs::read_to_string(ideal.join("summary.json")).unwrap();
    assert!(!summary.contains("\"mixer\""), "{summary}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn campaign_on_the_rotor_plant_counts_what_the_mixer_gave_up() {
    let dir = temp("campaign");
    let scenario = paper_with_rotors(&dir);
    let vehicle = preset_path("paper");
    for (name, extra) in [
        ("table", vec!["--scenario", scenario.to_str().unwrap()]),
        ("vehicle", vec!["--vehicle", vehicle.to_str().unwrap()]),
    ] {
        let out = dir.join(name);
        let mut args = vec![
            "campaign",
            "--plant",
            "rotors",
            "--runs",
            "3",
            "--duration-s",
            "4",
            "--converged-after-s",
            "4",
            "--no-plots",
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend(extra);
        let o = host_sim(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("campaign.json")).unwrap())
                .unwrap();
        assert_eq!(json["plant"], "rotors");
        let mixer = &json["results"]["mixer"]["nominal"];
        // Three runs of 4 s at 100 Hz: 401 samples each, every one through the mixer.
        assert_eq!(mixer["samples"], 3 * 401, "{json:#}");
        assert!(mixer["samples_given_up"].as_u64().is_some(), "{json:#}");
        assert!(
            mixer["thrust_given_up_max_N"].as_f64().is_some(),
            "{json:#}"
        );
        assert_eq!(json["results"]["mixer"]["perturbed"]["samples"], 0);
        let stdout = String::from_utf8_lossy(&o.stdout);
        assert!(
            stdout.contains("the mixer gave something up in"),
            "{stdout}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn rotor_plant_without_rotors_is_refused() {
    let out = temp("refused");
    let o = host_sim(&[
        "campaign",
        "--plant",
        "rotors",
        "--runs",
        "1",
        "--no-plots",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.contains("plant = rotors needs a [rotors] table (or --vehicle FILE)"),
        "{stderr}"
    );
    let o = host_sim(&[
        "--plant",
        "rotors",
        "--no-plots",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("needs a [rotors] table"));
    let _ = std::fs::remove_dir_all(&out);
}

/// `--motor-time-constant-s` replaces the vehicle's motor time constant on the rotor plant: the
/// main run changes, and a campaign counts its runs as perturbed.
#[test]
fn motor_time_constant_flag_replaces_the_vehicles() {
    let dir = temp("lag");
    let vehicle = preset_path("paper");
    let vehicle = vehicle.to_str().unwrap();
    let final_position = |extra: &[&str], name: &str| {
        let out = dir.join(name);
        let mut args = vec![
            "--vehicle",
            vehicle,
            "--plant",
            "rotors",
            "--no-plots",
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let o = host_sim(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let csv = std::fs::read_to_string(out.join("timeseries.csv")).unwrap();
        csv.lines().last().unwrap().to_string()
    };
    // paper.toml's own motor time constant is 0.02 s: passing it changes nothing, 0.05 s does.
    let own = final_position(&[], "own");
    assert_eq!(
        final_position(&["--motor-time-constant-s", "0.02"], "same"),
        own
    );
    assert_ne!(
        final_position(&["--motor-time-constant-s", "0.05"], "slow"),
        own
    );
    let o = host_sim(&[
        "--motor-time-constant-s=-1",
        "--no-plots",
        "--out",
        dir.join("bad").to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    assert!(
        String::from_utf8_lossy(&o.stderr)
            .contains("--motor-time-constant-s must be finite and >= 0, got -1"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let out = dir.join("campaign");
    let o = host_sim(&[
        "campaign",
        "--vehicle",
        vehicle,
        "--plant",
        "rotors",
        "--motor-time-constant-s",
        "0.04",
        "--runs",
        "2",
        "--duration-s",
        "2",
        "--converged-after-s",
        "2",
        "--no-plots",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("campaign.json")).unwrap()).unwrap();
    assert_eq!(
        json["results"]["mixer"]["nominal"]["samples"], 0,
        "{json:#}"
    );
    assert_eq!(
        json["results"]["mixer"]["perturbed"]["samples"],
        2 * 201,
        "{json:#}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
