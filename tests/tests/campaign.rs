//! A small campaign end to end: every run converges, no sample leaves the a-priori bounds, the
//! files are written, and the results do not depend on the number of threads.

use host_sim::campaign::output::{write_campaign, CampaignReport};
use host_sim::campaign::runner::bound_set;
use host_sim::campaign::{run_campaign, summarise, CampaignConfig, Convergence, SamplerRadii};
use host_sim::controllers::ControllerKind;
use host_sim::scenario::Scenario;

/// 24 runs of the 30 s paper scenario: the seven 180° starts, then Haar attitudes; offsets in
/// balls of 2 m, 1 m/s, 1 rad/s. The paper's law is slow to climb back after a 180° start
/// (`M_p = 2 m/s²`), so "converged" here is "inside 5 cm and 2° from 28 s on".
fn config(threads: usize) -> CampaignConfig {
    CampaignConfig {
        scenario: Scenario::paper(),
        controller: ControllerKind::Paper,
        runs: 24,
        seed: 42,
        radii: SamplerRadii {
            position_m: 2.0,
            velocity_m_s: 1.0,
            angular_velocity_rad_s: 1.0,
        },
        half_turns: true,
        convergence: Convergence {
            position_m: 0.05,
            attitude_deg: 2.0,
            after_s: 28.0,
        },
        progress: false,
        threads: Some(threads),
    }
}

#[test]
fn small_campaign_converges_within_the_bounds_and_writes_its_files() {
    let config = config(2);
    let results = run_campaign(&config).unwrap();
    let stats = summarise(&results, true);
    assert_eq!(stats.runs, 24);
    assert_eq!(stats.failed_runs, 0);
    assert_eq!(stats.converged, 24, "{:#?}", stats.settling_time_s);
    assert_eq!(stats.half_turn_runs, 7);
    assert_eq!(stats.nominal.samples, 24 * 3001);
    assert_eq!(stats.nominal.samples_outside_a_priori, 0);
    assert_eq!(stats.nominal.samples_beyond_limits, 0);
    let b = bound_set(&config.scenario).unwrap();
    assert!(stats.worst.thrust_max_N <= b.thrust_max_N);
    assert!(stats.worst.thrust_min_N >= b.thrust_min_N);
    for i in 0..3 {
        assert!(stats.worst.torque_abs_max_Nm[i] <= b.torque_max_Nm[i]);
    }
    // Final errors of the paper run: about 7.5e-5 m and 7.4e-5 deg (sample-and-hold lag).
    assert!(stats.final_position_error_m.max.unwrap() < 2e-4);

    let dir = std::env::temp_dir().join(format!("host-sim-campaign-test-{}", std::process::id()));
    let report = CampaignReport::new(&config, b, stats);
    let files = write_campaign(&dir, &report, &results, true).unwrap();
    let names: Vec<String> = files
        .iter()
        .map(|f| f.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    for expected in [
        "campaign.json",
        "runs.csv",
        "settling_histogram.png",
        "settling_cdf.png",
        "worst_thrust.png",
        "worst_torque.png",
        "final_error_scatter.png",
    ] {
        assert!(
            names.iter().any(|n| n == expected),
            "{expected} missing in {names:?}"
        );
    }
    for f in &files {
        assert!(
            std::fs::metadata(f).unwrap().len() > 100,
            "{} is empty",
            f.display()
        );
    }
    let json = std::fs::read_to_string(dir.join("campaign.json")).unwrap();
    assert!(json.contains("\"fraction_converged\": 1.0"), "{json}");
    assert!(json.contains("\"samples_outside_a_priori\": 0"), "{json}");
    assert!(
        json.contains("< 0.05 m and angle(R_d^T R) < 2 deg"),
        "{json}"
    );
    let csv = std::fs::read_to_string(dir.join("runs.csv")).unwrap();
    assert_eq!(csv.lines().count(), 25);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    let mut one = config(1);
    let mut two = config(2);
    for c in [&mut one, &mut two] {
        c.runs = 10;
        c.scenario.simulation.duration_s = 5.0;
        c.scenario.perturbations.gyro_noise_std_rad_s = 0.02;
        c.scenario.perturbations.mass_error_max_fraction = 0.1;
    }
    // Debug prints every float in full (shortest round-trip), so equal text is equal bits.
    let a = format!("{:?}", run_campaign(&one).unwrap());
    let b = format!("{:?}", run_campaign(&two).unwrap());
    assert_eq!(a, b);
}

#[test]
fn perturbed_runs_are_counted_apart_from_nominal_ones() {
    let mut c = config(2);
    c.runs = 8;
    c.scenario.simulation.duration_s = 5.0;
    c.scenario.perturbations.torque_disturbance_Nm = [0.01, 0.0, 0.0];
    assert!(c.scenario.perturbations.violates_model());
    let results = run_campaign(&c).unwrap();
    let stats = summarise(&results, !c.scenario.perturbations.violates_model());
    assert_eq!(stats.nominal.runs, 0);
    assert_eq!(stats.perturbed.runs, 8);
    assert_eq!(stats.perturbed.samples, 8 * 501);
}
