//! Tilt-priority attitude feedback (controller-core's `tilt_priority`, docs/tilt-priority.md)
//! on the paper's vehicle: the scenario file, its certificate and the recovery it buys.

use host_sim::model::scenario::Scenario;
use host_sim::studies::ablation::no_dive::hover_half_turns;

fn scenario(name: &str) -> Scenario {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenarios")
        .join(name);
    Scenario::load(&path).unwrap()
}

/// Given the paper's law and the tilt-priority scenario (with the no-dive thrust), when each
/// flies the seven 180° starts at hover, then the tilt-priority scenario loses at most half the
/// altitude the paper's law loses from every start (the target tilt priority was built for), and settles from each.
#[test]
fn tilt_priority_halves_the_altitude_lost_from_every_half_turn() {
    let paper = hover_half_turns(&Scenario::paper()).unwrap();
    let tilt = hover_half_turns(&scenario("paper-tilt-priority.toml")).unwrap();
    assert_eq!(paper.len(), 7);
    for ((label, lost_paper, _), (label_tilt, lost_tilt, settled)) in paper.iter().zip(&tilt) {
        assert_eq!(label, label_tilt);
        // The z half turn keeps the thrust axis up: neither law loses altitude there.
        let allowed = (0.5 * lost_paper).max(0.01);
        assert!(
            *lost_tilt <= allowed,
            "{label}: {lost_tilt:.2} m lost, paper's law {lost_paper:.2} m"
        );
        assert!(settled.is_some(), "{label}: not settled");
    }
}

/// The scenario is the paper-no-dive scenario with only the attitude feedback changed, and its
/// certificate reports the per-axis levels and the hysteresis-band condition (which holds).
#[test]
fn tilt_priority_scenario_is_certified_per_axis() {
    let tilt = scenario("paper-tilt-priority.toml");
    let no_dive = scenario("paper-no-dive.toml");
    let mut same = tilt.clone();
    same.gains = no_dive.gains.clone();
    assert_eq!(same, no_dive);
    let cert = host_sim::fly::sim::certificate(&tilt).unwrap();
    let levels = cert.bounds.feedback_torque_axes;
    let t = tilt.gains.tilt_priority.unwrap();
    let radial = (1.0 + 1.02f64.powi(2)) * tilt.gains.M_theta / 4.0;
    let g = t.trace_weights_Nm;
    let expected = [
        radial + 0.5 * (g[1] + g[2]) + t.omega_levels_Nm[0],
        radial + 0.5 * (g[2] + g[0]) + t.omega_levels_Nm[1],
        radial + 0.5 * (g[0] + g[1]) + t.omega_levels_Nm[2],
    ];
    for i in 0..3 {
        approx::assert_relative_eq!(levels[i], expected[i], max_relative = 1e-12);
    }
    let band = cert
        .all_conditions()
        .find(|c| c.name == "tilt_priority.hysteresis_band")
        .unwrap();
    assert!(band.holds, "{band:?}");
}

/// Bad `[gains.tilt_priority]` tables are refused with the file and the key.
#[test]
fn tilt_priority_keys_are_checked_by_name() {
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/paper-tilt-priority.toml"),
    )
    .unwrap();
    let bad = text.replace(
        "trace_weights_Nm = [0.05, 0.05, 0.3]",
        "trace_weights_Nm = [0.05, -0.05, 0.3]",
    );
    assert_ne!(bad, text);
    let e = format!("{:#}", Scenario::parse(&bad, "neg.toml").unwrap_err());
    assert!(
        e.contains("neg.toml") && e.contains("gains.tilt_priority.trace_weights_Nm"),
        "{e}"
    );
    let unknown = text.replace("omega_gains_Nm_s", "omega_gain_Nm_s");
    let e = format!(
        "{:#}",
        Scenario::parse(&unknown, "unknown.toml").unwrap_err()
    );
    assert!(
        e.contains("unknown.toml") && e.contains("omega_gain_Nm_s"),
        "{e}"
    );
}
