//! `scenarios/mass-error.toml`: the paper's helix and vehicle, plant mass +20 %, the bounded
//! integral action on (docs/integral-action.md). Its extended certificate holds, and the run
//! ends within 1 cm of the reference with every sample inside the a-priori bounds; without the
//! integral action the same set-up does not.

use host_sim::scenario::Scenario;
use host_sim::sim::{certificate, run_summary};

const TEXT: &str = include_str!("../scenarios/mass-error.toml");

fn scenario() -> Scenario {
    Scenario::parse(TEXT, "mass-error.toml").unwrap()
}

#[test]
fn extended_certificate_holds() {
    let s = scenario();
    assert!(s.gains::<f64>().integral.is_some());
    assert_eq!(s.perturbations.mass_error_fraction, 0.2);
    let c = certificate(&s).unwrap();
    assert!(c.require_feasible().is_ok(), "{:?}", c.require_feasible());
    let i = c.integral.unwrap();
    assert!(i.conditions.iter().all(|k| k.holds));
}

#[test]
fn integral_action_removes_the_mass_error_and_stays_in_bounds() {
    let summary = run_summary(&scenario()).unwrap();
    assert!(
        summary.final_.position_error_m < 0.01,
        "{:?}",
        summary.final_
    );
    assert_eq!(summary.observed.samples_outside_a_priori_bounds, 0);
    assert!(summary.a_priori.feasible);
    assert!(summary.a_priori.integral.is_some());
    // The tight bounds cover the integral estimate (it widens their confining set): reported,
    // below the extended paper bounds, and no sample above them.
    let t = &summary.a_priori.tight;
    for i in 0..3 {
        assert!(
            t.torque_max_Nm[i] < summary.a_priori.torque_max_Nm[i],
            "{t:?}"
        );
    }
    assert!(t.feasible, "{t:?}");
    assert_eq!(summary.observed.samples_above_tight_bounds, 0);

    let mut without = scenario();
    without.gains.integral = None;
    let summary = run_summary(&without).unwrap();
    assert!(
        summary.final_.position_error_m > 0.1,
        "{:?}",
        summary.final_
    );
}
