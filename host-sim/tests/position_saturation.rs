//! The norm-saturated position feedback (docs/position-saturation.md) end to end: read from a
//! scenario file, flown on the paper's Section VI start (upside down, 9.2 m off), every sample
//! inside its own a-priori bounds, and the √3 of Theorem 1 given back as `M_p`.

use host_sim::fly::sim::run;
use host_sim::model::scenario::{PositionSaturationConfig, Scenario};

/// The paper's scenario with `position_saturation = "norm"` and `M_p` as given.
fn norm_paper(saturation: f64) -> Scenario {
    let text = toml::to_string(&Scenario::paper()).expect("the paper scenario serialises");
    let text = text.replacen("[gains]\n", "[gains]\nposition_saturation = \"norm\"\n", 1);
    let mut s = Scenario::parse(&text, "norm_paper").expect("the key is read");
    assert_eq!(s.gains.position_saturation, PositionSaturationConfig::Norm);
    s.gains.M_p = saturation;
    s
}

/// Given Table I with the norm shape, when the paper's run is flown, then it recovers as the
/// paper's does (below 1 mm at 30 s), with no sample outside its a-priori bounds, and those
/// bounds are tighter than the paper's shape's for the same `M_p` (T_max, U_ωd, U_ω̇d, every
/// torque), with the same `T_min`.
#[test]
fn the_paper_run_with_the_norm_shape_stays_inside_tighter_bounds() {
    let (paper, _) = run(&Scenario::paper()).expect("the paper's run");
    let (norm, _) = run(&norm_paper(Scenario::paper().gains.M_p)).expect("the norm run");
    assert_eq!(norm.observed.samples_outside_a_priori_bounds, 0);
    assert!(
        norm.final_.position_error_m < 1e-3,
        "{}",
        norm.final_.position_error_m
    );
    let (a, b) = (&norm.a_priori, &paper.a_priori);
    assert_eq!(a.thrust_min_N, b.thrust_min_N);
    assert!(a.thrust_max_N < b.thrust_max_N);
    assert!(a.angular_velocity_max_rad_s < b.angular_velocity_max_rad_s);
    assert!(a.angular_acceleration_max_rad_s2 < b.angular_acceleration_max_rad_s2);
    for i in 0..3 {
        assert!(a.torque_max_Nm[i] < b.torque_max_Nm[i]);
    }
}

/// Given the norm shape with `M_p` raised until its `T_max` is the paper's (`√3 M_p` of the
/// paper's shape = `M_p'` of the norm shape), when the paper's run is flown, then the thrust the
/// certificate allows is the same, the run stays inside it, and the vehicle brakes harder: it
/// loses less altitude from the paper's upside-down start than with Table I.
#[test]
fn the_same_thrust_interval_buys_sqrt3_times_the_level() {
    let table1 = Scenario::paper().gains.M_p;
    let (paper, _) = run(&Scenario::paper()).expect("the paper's run");
    let (norm, _) = run(&norm_paper(3f64.sqrt() * table1)).expect("the norm run");
    let rel = (norm.a_priori.thrust_max_N - paper.a_priori.thrust_max_N).abs()
        / paper.a_priori.thrust_max_N;
    assert!(
        rel < 1e-12,
        "T_max {} vs {}",
        norm.a_priori.thrust_max_N,
        paper.a_priori.thrust_max_N
    );
    assert_eq!(norm.observed.samples_outside_a_priori_bounds, 0);
    assert!(norm.observed.thrust_max_N <= norm.a_priori.thrust_max_N);
    assert!(
        norm.observed.altitude_loss_m < paper.observed.altitude_loss_m,
        "{} m vs {} m",
        norm.observed.altitude_loss_m,
        paper.observed.altitude_loss_m
    );
}

/// Given a scenario file with an unknown shape, when it is read, then it is refused naming the
/// key.
#[test]
fn an_unknown_shape_is_refused() {
    let text = toml::to_string(&Scenario::paper())
        .expect("the paper scenario serialises")
        .replacen(
            "[gains]\n",
            "[gains]\nposition_saturation = \"radial\"\n",
            1,
        );
    let err = Scenario::parse(&text, "bad").unwrap_err();
    assert!(
        format!("{err:#}").contains("position_saturation"),
        "{err:#}"
    );
}
