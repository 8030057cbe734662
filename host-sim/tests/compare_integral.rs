//! `host-sim compare` on a scenario with the bounded integral action: the
//! paper's law flies it with and without `[gains.integral]` beside the baselines, each checked
//! against its own bounds (the extended certificate's with it, the paper's without).
//!
//! Given `integral-campaign.toml` (certified with its integral action) and a constant force of
//! about 8 % of the weight, when compared on a few runs, then the row with the integral action
//! removes the force's steady error that the row without it keeps, and neither row leaves its
//! own a-priori bounds.

use host_sim::fly::controllers::ControllerKind;
use host_sim::model::scenario::Scenario;
use host_sim::studies::compare::{contestants, run_compare};

const TEXT: &str = include_str!("../scenarios/integral-campaign.toml");

fn scenario() -> Scenario {
    let mut s = Scenario::parse(TEXT, "integral-campaign.toml").unwrap();
    s.simulation.duration_s = 30.0;
    s.perturbations.force_disturbance_N = [0.3, 0.0, -0.2];
    s
}

#[test]
fn contestants_carry_the_integral_only_when_the_scenario_has_it() {
    let with = scenario();
    let labels: Vec<_> = contestants(&with).into_iter().map(|c| c.label).collect();
    assert_eq!(
        labels,
        ["paper + integral", "paper", "lee", "lee (clipped)", "px4"]
    );
    let without_table = contestants(&with)[1].scenario(&with);
    assert!(without_table.gains.integral.is_none());
    assert!(contestants(&with)[0]
        .scenario(&with)
        .gains
        .integral
        .is_some());

    let mut plain = scenario();
    plain.gains.integral = None;
    let labels: Vec<_> = contestants(&plain).into_iter().map(|c| c.label).collect();
    assert_eq!(labels, ["paper", "lee", "lee (clipped)", "px4"]);
}

#[test]
fn with_and_without_rows_under_a_constant_force() {
    let (report, _) = run_compare(&scenario(), 6, 3).unwrap();
    let paper_rows: Vec<_> = report
        .results
        .iter()
        .filter(|r| r.contestant.controller == ControllerKind::Paper)
        .collect();
    let [with, without] = paper_rows[..] else {
        panic!(
            "expected two rows of the paper's law, got {}",
            paper_rows.len()
        );
    };
    assert!(with.contestant.integral && !without.contestant.integral);

    // Each row is checked against its own bounds: the extended ones are wider (the lower
    // end of the interval is the no-dive thrust's floor in both).
    assert!(with.bounds.thrust_max_N > without.bounds.thrust_max_N);
    for i in 0..3 {
        assert!(with.bounds.torque_max_Nm[i] > without.bounds.torque_max_Nm[i]);
    }
    assert_eq!(with.bounds, report.bounds);

    for row in [with, without] {
        let counts = &row.campaign.perturbed;
        assert!(
            counts.samples > 0,
            "{}: the force makes every run perturbed",
            row.contestant.label
        );
        assert_eq!(
            counts.samples_outside_a_priori, 0,
            "{}",
            row.contestant.label
        );
        assert_eq!(row.half_turns.perturbed.samples_outside_a_priori, 0);
    }

    // The force (0.36 N, 8 % of the weight) leaves the paper's law centimetres off; the
    // integral action removes it.
    let steady = |r: &host_sim::studies::compare::ContestantResult| {
        r.campaign
            .steady_position_error_m
            .p50
            .unwrap_or(f64::INFINITY)
    };
    let (e_with, e_without) = (steady(with), steady(without));
    assert!(e_without > 0.01, "without: {e_without} m");
    assert!(
        e_with < e_without / 10.0,
        "with {e_with} m, without {e_without} m"
    );
}
