//! Given/when/then checks of [`super::score_scenario`] against what `design` itself computed
//! for the committed x500 design (its `design.json`), and on edits a user would try.

use super::score_scenario;
use crate::design::integral::IntegralSpec;
use crate::model::scenario::Scenario;

fn x500() -> (Scenario, serde_json::Value) {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("designs/x500");
    let scenario = Scenario::load(&dir.join("scenario.toml")).unwrap();
    let text = std::fs::read_to_string(dir.join("design.json")).unwrap();
    (scenario, serde_json::from_str(&text).unwrap())
}

fn covered(json: &serde_json::Value, scenario: &Scenario) -> IntegralSpec {
    let i = &json["integral"];
    IntegralSpec::covering(
        scenario.vehicle.gravity_m_s2,
        i["mass_error_fraction"].as_f64().unwrap(),
        i["force_fraction"].as_f64().unwrap(),
    )
    .unwrap()
}

/// Given the committed x500 design, when its scenario file is scored with the disturbance and
/// margin it was designed for, then it is certified (and by the firmware's gate), its fit
/// headroom is the report's, and the objective and its upside-down and half-turn figures are
/// the ones `design` computed when it chose these gains.
#[test]
fn the_committed_x500_design_scores_as_design_scored_it() {
    let (scenario, json) = x500();
    let spec = covered(&json, &scenario);
    let margin = json["rotor_fit"]["requested_margin"].as_f64().unwrap();
    let s = score_scenario(&scenario, Some(&spec), margin).unwrap();
    assert!(s.certified && s.gate_certified, "{:?}", s.violated);
    assert!(s.violated.is_empty());
    let fit = json["rotor_fit"]["margin"].as_f64().unwrap();
    assert!(
        (s.fit_headroom - fit).abs() < 1e-9,
        "{} vs {fit}",
        s.fit_headroom
    );
    // The local set fits with the margin too (the gate's `rotor_fit.local_shadow`).
    assert!(s.local_fit_headroom.unwrap() >= margin);
    let o = &json["objective"];
    let e = &s.evaluation;
    assert!(e.feasible);
    let close = |a: f64, b: &serde_json::Value| (a - b.as_f64().unwrap()).abs() < 1e-9;
    assert!(close(e.cost, &o["value"]), "{} vs {}", e.cost, o["value"]);
    assert!(close(
        e.altitude_loss_upside_down_m,
        &o["altitude_loss_upside_down_m"]
    ));
    assert!(close(
        e.worst_settling_180_s.unwrap(),
        &o["worst_settling_180_s"]
    ));
}

/// Given the x500 design with its local position level raised to 2.5 m/s² (a user chasing a
/// faster step), when it is scored, then it is refused and the report names the local regime's
/// yaw condition with its numbers (the local torque set asks more yaw torque than the rotors
/// give), and the local set's headroom is negative.
#[test]
fn a_local_level_the_yaw_cannot_pay_for_is_refused_by_name() {
    let (mut scenario, _) = x500();
    scenario.gains.local.as_mut().unwrap().M_p_m_s2 = 2.5;
    let s = score_scenario(&scenario, None, 0.05).unwrap();
    assert!(!s.certified && !s.gate_certified);
    let yaw = s
        .violated
        .iter()
        .find(|v| v.name == "local_regime.torque_max_yaw")
        .expect("the local yaw condition fails");
    assert!(yaw.lhs <= yaw.rhs, "{yaw:?}");
    assert!(
        s.local_fit_headroom.unwrap() < 0.0,
        "{:?}",
        s.local_fit_headroom
    );
}

/// Given a scenario without a `[rotors]` table (the paper's), when it is scored, then it is
/// refused with a message that names the table, instead of judging a fit it cannot make.
#[test]
fn a_scenario_without_rotors_is_refused() {
    let e = score_scenario(&Scenario::paper(), None, 0.05).unwrap_err();
    assert!(e.to_string().contains("[rotors]"), "{e}");
}
