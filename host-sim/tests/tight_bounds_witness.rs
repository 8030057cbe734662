//! Soundness sampling and witnesses of the a-priori bounds (`host_sim::bounds::tight`).
//!
//! - Dense seeded sampling of the confining set (10⁵ admissible states per set-up, plus the
//!   witnesses, which are the most demanding states found) never exceeds the bounds under test:
//!   tight ones (`host_sim::bounds::tight::tight_bounds`, including its `H₁₂`, `H₃`) for the
//!   paper's set-up and the Crazyflie design, from both filter start sets.
//! - The witnesses are admissible (checked on their stored values, independently of the
//!   parameter map), re-evaluate to their values from their stored parameters, stay below the
//!   paper's bounds, and lie above the largest values a campaign of flown runs reaches.

use std::path::PathBuf;

use controller_core::FilterStart;
use host_sim::bounds::tight::sampling::{sample, AdmissibleState};
use host_sim::bounds::tight::setup::Setup;
use host_sim::bounds::tight::witness::{witnesses, Quantity, WitnessBudget, Witnesses, QUANTITIES};
use host_sim::fly::controllers::ControllerKind;
use host_sim::model::scenario::Scenario;
use host_sim::runs::metrics::Convergence;
use host_sim::runs::runner::{run_campaign, CampaignConfig};
use host_sim::runs::sampler::SamplerRadii;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// Upper bounds on `|ω_d|` [rad/s], `|ω̇_d|` [rad/s²] and `|τ_i|` [N m], with the field names
/// of `host_sim::bounds::tight::TightBounds`.
struct Bound {
    angular_velocity: f64,
    angular_acceleration: f64,
    horizontal_acceleration: f64,
    yaw_acceleration: f64,
    torque_max: [f64; 3],
}

/// The paper's bounds: Lemma 1 and Theorem 2 (`controller_core::certify`).
fn paper_bound(setup: &Setup) -> Bound {
    let b = setup.certificate().expect("the set-up certifies").bounds;
    Bound {
        angular_velocity: b.angular_velocity,
        angular_acceleration: b.angular_acceleration,
        // Lemma 1 bounds only the norm, hence each part.
        horizontal_acceleration: b.angular_acceleration,
        yaw_acceleration: b.angular_acceleration,
        torque_max: b.torque_max.into(),
    }
}

/// The bounds the samples are checked against: the tight ones.
fn bound_under_test(setup: &Setup) -> Bound {
    let t = host_sim::bounds::tight::tight_bounds(
        &setup.vehicle,
        &setup.gains,
        &setup.constants,
        setup.filter_start,
        &Default::default(),
    )
    .expect("the set-up has tight bounds");
    Bound {
        angular_velocity: t.angular_velocity,
        angular_acceleration: t.angular_acceleration,
        horizontal_acceleration: t.horizontal_acceleration,
        yaw_acceleration: t.yaw_acceleration,
        torque_max: t.torque_max,
    }
}
fn crazyflie() -> Setup {
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("designs/crazyflie-2.1/scenario.toml");
    Setup::from_scenario(&Scenario::load(&path).expect("the Crazyflie design loads"))
}

/// The bound of `q` in `b`.
fn bound_of(b: &Bound, q: Quantity) -> f64 {
    match q {
        Quantity::AngularVelocity => b.angular_velocity,
        Quantity::AngularAcceleration => b.angular_acceleration,
        Quantity::HorizontalAngularAcceleration => b.horizontal_acceleration,
        Quantity::YawAngularAcceleration => b.yaw_acceleration,
        Quantity::Torque(i) => b.torque_max[i],
    }
}

/// Every quantity of the law at `state` is within `bound`; returns the values.
fn assert_within(setup: &Setup, bound: &Bound, state: &AdmissibleState, what: &str) -> [f64; 7] {
    if let Err(e) = state.check(setup) {
        panic!("{what}: not admissible: {e}\n{state:?}");
    }
    let values = state
        .evaluate(setup)
        .unwrap_or_else(|e| panic!("{what}: the law refuses an admissible state: {e:?}"));
    QUANTITIES.map(|q| {
        let v = q.of(&values);
        assert!(
            v <= bound_of(bound, q),
            "{what}: {} = {v} exceeds its bound {}\n{state:?}",
            q.name(),
            bound_of(bound, q)
        );
        v
    })
}

/// 10⁵ seeded samples and the witnesses of `setup` stay within the bounds under test; the
/// largest sampled values are printed beside the bounds.
fn check_sampled_states(setup: &Setup, name: &str) {
    const SAMPLES: usize = 100_000;
    let bound = bound_under_test(setup);
    let mut rng = ChaCha8Rng::seed_from_u64(0x5eed);
    let mut largest = [0.0f64; 7];
    for k in 0..SAMPLES {
        let values = assert_within(
            setup,
            &bound,
            &sample(&mut rng, setup),
            &format!("{name} sample {k}"),
        );
        for (l, v) in largest.iter_mut().zip(values) {
            *l = l.max(v);
        }
    }
    let found = witnesses(setup, 11, &WitnessBudget::default()).expect("witness search runs");
    for w in &found.all {
        assert_within(
            setup,
            &bound,
            &w.state,
            &format!("{name} witness of {}", w.quantity.name()),
        );
    }
    for (q, l) in QUANTITIES.iter().zip(largest) {
        println!(
            "{name}: {}: sampled max {l:.4}, witness {:.4}, bound {:.4}",
            q.name(),
            found.get(*q).value,
            bound_of(&bound, *q)
        );
    }
}

#[test]
fn sampled_states_respect_the_bounds_paper() {
    check_sampled_states(&Setup::paper(), "paper");
}

#[test]
fn sampled_states_respect_the_bounds_crazyflie() {
    check_sampled_states(&crazyflie(), "crazyflie-2.1");
}

fn mass_error() -> Setup {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenarios/mass-error.toml");
    Setup::from_scenario(&Scenario::load(&path).expect("the mass-error scenario loads"))
}

/// With the integral action on (`scenarios/mass-error.toml`), the samples carry an integral
/// state (`η`, `η̇` often at their limits, `η_f` in the reachable set around `η`) and stay
/// within the tight bounds of the widened confining set; the widened bounds are larger than
/// without the estimate, and the witnesses with it reach further than without it.
#[test]
fn sampled_states_respect_the_bounds_integral_action() {
    let setup = mass_error();
    let integral = setup.gains.integral.expect("the integral action is on");
    check_sampled_states(&setup, "mass-error");
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let at_level = (0..1000)
        .filter(|_| {
            let s = sample(&mut rng, &setup);
            (s.integral.filtered.z.abs() - integral.level.z).abs() < 1e-12
        })
        .count();
    assert!(
        at_level > 100,
        "{at_level} of 1000 samples with η_f,z at its level"
    );
    let mut off = setup;
    off.gains.integral = None;
    let bound_without = bound_under_test(&off);
    let bound_with = bound_under_test(&setup);
    let found = witnesses(&setup, 11, &WitnessBudget::default()).expect("witness search runs");
    let found_off = witnesses(&off, 11, &WitnessBudget::default()).expect("witness search runs");
    // The confining set is widened: every bound is larger with the estimate than without.
    assert!(bound_with.angular_velocity > bound_without.angular_velocity);
    assert!(bound_with.angular_acceleration > bound_without.angular_acceleration);
    // And the widening is used: over the reachable integral states the law reaches further
    // than any state of the law without the estimate that the same search finds.
    let pairs = [Quantity::AngularVelocity, Quantity::AngularAcceleration];
    let report: Vec<String> = pairs
        .iter()
        .map(|q| {
            format!(
                "{q:?}: with {} / without {}",
                found.get(*q).value,
                found_off.get(*q).value
            )
        })
        .collect();
    assert!(
        pairs
            .iter()
            .any(|q| found.get(*q).value > found_off.get(*q).value),
        "{report:?}"
    );
}

/// Filters started anywhere in the saturation box: samples stay admissible and within the
/// paper's bounds for that start (Lemma 1 with `U_l = 1`).
#[test]
fn sampled_states_respect_the_bounds_box_start() {
    let mut setup = Setup::paper();
    setup.filter_start = FilterStart::InSaturationBox;
    let bound = paper_bound(&setup);
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let mut started_off_zero = 0;
    for k in 0..20_000 {
        let s = sample(&mut rng, &setup);
        started_off_zero += usize::from(s.filters.iter().any(|f| f.start != [0.0; 2]));
        assert_within(&setup, &bound, &s, &format!("box-start sample {k}"));
    }
    assert!(started_off_zero > 10_000, "{started_off_zero}");
}

/// The largest `|ω_d|`, `|ω̇_d|`, `|τ_i|` over a campaign of flown runs of `scenario` (the
/// seven 180° starts and random starts), as the campaign measures them.
fn campaign_peaks(scenario: &Scenario, runs: u64) -> (f64, f64, [f64; 3]) {
    let config = CampaignConfig {
        scenario: scenario.clone(),
        controller: ControllerKind::Paper,
        runs,
        seed: 1,
        radii: SamplerRadii::default(),
        half_turns: true,
        convergence: Convergence::default(),
        progress: false,
        threads: None,
    };
    let results = run_campaign(&config).expect("the campaign runs");
    let mut peaks = (0.0f64, 0.0f64, [0.0f64; 3]);
    for m in results.iter().filter_map(|r| r.metrics.as_ref()) {
        peaks.0 = peaks.0.max(m.omega_d_max_rad_s);
        peaks.1 = peaks.1.max(m.omega_d_dot_max_rad_s2);
        for (p, t) in peaks.2.iter_mut().zip(m.torque_abs_max_Nm) {
            *p = p.max(t);
        }
    }
    assert!(peaks.1 > 0.0, "the campaign measured nothing");
    peaks
}

/// Each witness is admissible, its stored parameters give back its state and value, it is
/// below the paper's bound and above what flown runs reach.
#[test]
fn witnesses_are_admissible_below_the_paper_and_above_flown_runs() {
    let setup = Setup::paper();
    let found: Witnesses = witnesses(&setup, 5, &WitnessBudget::default()).unwrap();
    let paper = paper_bound(&setup);
    for w in &found.all {
        w.state.check(&setup).unwrap();
        let again = AdmissibleState::from_parameters(&setup, &w.parameters);
        assert_eq!(again, w.state, "{}", w.quantity.name());
        let value = w.quantity.of(&again.evaluate(&setup).unwrap());
        assert_eq!(value, w.value, "{}", w.quantity.name());
        assert!(
            value <= bound_of(&paper, w.quantity),
            "{}",
            w.quantity.name()
        );
    }
    // The horizontal and yaw parts of ω̇_d are parts of its norm.
    let norm = found.get(Quantity::AngularAcceleration).value;
    assert!(found.get(Quantity::HorizontalAngularAcceleration).value <= norm * (1.0 + 1e-12));
    assert!(found.get(Quantity::YawAngularAcceleration).value <= norm * (1.0 + 1e-12));

    let (w_max, w_dot_max, tau_max) = campaign_peaks(&Scenario::paper(), 48);
    println!("flown runs: |omega_d| {w_max:.3}, |omega_d_dot| {w_dot_max:.3}, |tau| {tau_max:.4?}");
    assert!(found.get(Quantity::AngularVelocity).value > w_max);
    assert!(found.get(Quantity::AngularAcceleration).value > w_dot_max);
    for (i, t) in tau_max.iter().enumerate() {
        assert!(found.get(Quantity::Torque(i)).value > *t, "axis {i}");
    }
}

/// The search is deterministic for a seed (parallel parts are collected in order).
#[test]
fn witness_search_is_deterministic() {
    let setup = Setup::paper();
    let small = WitnessBudget {
        samples: 3000,
        restarts: 2,
        evaluations: 3000,
    };
    let a = witnesses(&setup, 9, &small).unwrap();
    let b = witnesses(&setup, 9, &small).unwrap();
    assert_eq!(a, b);
}

/// The searches that keep the filter correlations (`tight_bounds::coupled_search`) bound, on
/// their own, every sampled admissible state and every witness of `|(ω̇_d1, ω̇_d2)|` and
/// `|ω̇_d|`: for the paper's set-up from both filter start sets and with the integral action
/// on. Their bound is over a smaller superset of the confining set than the product of boxes,
/// so this checks the polygon of the filter states (every sampled filter state lies in it) and
/// `ü` tied to them.
#[test]
fn coupled_searches_bound_the_samples() {
    use host_sim::bounds::tight::confining_set::ConfiningSet;
    use host_sim::bounds::tight::coupled_search::maximise_coupled;
    use host_sim::bounds::tight::filter_polygon::FilterPolygon;
    use host_sim::bounds::tight::search::Quantity as Searched;
    let mut box_start = Setup::paper();
    box_start.filter_start = FilterStart::InSaturationBox;
    for (setup, name) in [
        (Setup::paper(), "paper"),
        (box_start, "paper, box start"),
        (mass_error(), "mass-error"),
    ] {
        let set = ConfiningSet::new(
            &setup.vehicle,
            &setup.gains,
            &setup.constants,
            setup.filter_start,
        )
        .expect("the set-up has a confining set");
        let polygon = FilterPolygon::new(
            &setup.vehicle,
            &setup.gains,
            &setup.constants,
            setup.filter_start,
        );
        let search = |q| {
            maximise_coupled(&set, &polygon, q, 0.01, 200_000)
                .expect("an ω̇_d quantity")
                .upper
        };
        let (horizontal, total) = rayon::join(
            || search(Searched::HorizontalAcceleration),
            || search(Searched::AngularAcceleration),
        );
        let found = witnesses(&setup, 11, &WitnessBudget::default()).expect("witness search runs");
        let mut rng = ChaCha8Rng::seed_from_u64(0xc0);
        let mut states: Vec<AdmissibleState> =
            (0..20_000).map(|_| sample(&mut rng, &setup)).collect();
        states.extend(found.all.iter().map(|w| w.state));
        let mut largest = [0.0f64; 2];
        for (k, state) in states.iter().enumerate() {
            // The polygon holds every filter state the sampler reaches (exact propagation
            // from the start set under piecewise-constant and bang-bang inputs).
            for (c, history) in state.filters.iter().enumerate() {
                let [uf, us] = history.end_state(&setup.gains.position);
                assert!(
                    polygon.admits(uf, us - uf),
                    "{name} state {k}: component {c}'s filter state ({uf}, {}) outside the polygon",
                    us - uf
                );
            }
            let values = state
                .evaluate(&setup)
                .unwrap_or_else(|e| panic!("{name} state {k}: {e:?}"));
            for (l, (q, b)) in largest.iter_mut().zip([
                (Quantity::HorizontalAngularAcceleration, horizontal),
                (Quantity::AngularAcceleration, total),
            ]) {
                let v = q.of(&values);
                assert!(
                    v <= b,
                    "{name} state {k}: {} = {v} above {b}\n{state:?}",
                    q.name()
                );
                *l = l.max(v);
            }
        }
        println!(
            "{name}: coupled bounds {horizontal:.3} / {total:.3}, largest values {:.3} / {:.3}",
            largest[0], largest[1]
        );
    }
}
