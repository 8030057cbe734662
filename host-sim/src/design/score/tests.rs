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
    // The aligned fit is the report's, and so is its verdict on airmode's convergence proof.
    let aligned = json["rotor_fit"]["aligned_margin"].as_f64().unwrap();
    let a = s.aligned_fit_headroom.unwrap();
    assert!((a - aligned).abs() < 1e-12, "{a} vs {aligned}");
    let proven = json["rotor_fit"]["airmode_convergence_proven"]
        .as_bool()
        .unwrap();
    assert_eq!(a >= margin, proven);
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

/// Given the x500 design with its local position level raised to 4 m/s² (a user chasing a
/// faster step; at 2.5 m/s² its set no longer fits, every condition still holding), when it is scored, then it is refused and the report names the local regime's
/// yaw condition with its numbers (the local torque set asks more yaw torque than the rotors
/// give), and the local set's headroom is negative.
#[test]
fn a_local_level_the_yaw_cannot_pay_for_is_refused_by_name() {
    let (mut scenario, _) = x500();
    scenario.gains.local.as_mut().unwrap().M_p_m_s2 = 4.0;
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

/// Given the committed x500 design (airmode), when it is scored, then the certified set's and
/// the local set's binding pairs carry the fits' own headrooms, each asks the sum of its parts
/// and no more than the pair's capacity less the margin, the pair is one of opposite spins
/// (rotors 1 and 3 of the file, ccw and cw: yaw splits them), and the certified set's
/// feedforward spends most of its share on the yaw axis (the desired tilt acceleration turned
/// onto yaw, docs/results.md), while the local set's budget is mostly its aligned feedforward.
#[test]
fn the_x500s_binding_pairs_split_their_budget() {
    let (scenario, json) = x500();
    let margin = json["rotor_fit"]["requested_margin"].as_f64().unwrap();
    let s = score_scenario(&scenario, None, margin).unwrap();
    let spins = &scenario.rotors.as_ref().unwrap().spin;
    for (b, headroom) in [
        (s.binding.as_ref().unwrap(), s.fit_headroom),
        (
            s.local_binding.as_ref().unwrap(),
            s.local_fit_headroom.unwrap(),
        ),
    ] {
        assert!(
            (b.margin - headroom).abs() < 1e-12,
            "{} vs {headroom}",
            b.margin
        );
        let p = &b.parts;
        let sum = p.feedforward_n
            + p.gyroscopic_n
            + p.feedback_ball_n
            + p.feedback_box_n
            + p.feedback_disks_n
            + p.aligned_n
            - p.joint_saving_n;
        assert!(
            (sum - b.asked_n).abs() < 1e-12 * b.asked_n,
            "{sum} vs {}",
            b.asked_n
        );
        assert!(b.asked_n <= b.capacity_n - margin * b.margin_unit_n);
        // The margin is the slack in units of the pair's range, recomputed from the fields.
        let slack = (b.capacity_n - b.asked_n) / b.margin_unit_n;
        assert!((slack - b.margin).abs() < 1e-12, "{slack} vs {}", b.margin);
        assert_ne!(
            spins[b.rotors.0 - 1],
            spins[b.rotors.1 - 1],
            "{:?}",
            b.rotors
        );
    }
    let g = &s.binding.as_ref().unwrap().parts;
    assert!(g.feedforward_yaw_n > 0.9 * g.feedforward_n, "{g:?}");
    let l = s.local_binding.as_ref().unwrap();
    assert!(l.parts.aligned_n > 0.8 * l.asked_n, "{:?}", l.parts);
}
