//! Tests of [`super`]: the default and certified integral gains, the convergence horizon, the
//! case table.

use super::*;

/// The default gains satisfy the extended certificate's Theorem 1 and Routh–Hurwitz
/// conditions on the paper's set-up (Theorem 2's yaw condition already fails without them).
#[test]
fn default_gains_certify_on_the_paper_setup() {
    let s = Scenario::paper();
    let (g, source) = integral_gains_of(&s);
    assert_eq!(source, "default");
    let cert = extended_certificate(&s, &g).unwrap();
    for c in cert.all_conditions() {
        if !c.name.starts_with("theorem2") {
            assert!(c.holds, "{c:?}");
        }
    }
    assert!(cert.integral.is_some());
}

/// A configuration of the paper's vehicle, limits and helix for which every condition of
/// the extended certificate holds (Theorem 2's yaw condition included): `M_p` lowered to
/// 1.25 m/s², the integral level `M_p / 4`, with a slow output filter (`k_η = 1 /s`) and
/// with the default `k_η = 5 /s` too, because its rate limit `R = 1 m/s³` caps `|η̇_f|` at
/// about `R` over the reachable states (controller_core::integral), below `2 k_η M_i`. With
/// the rate limit raised to `2 k_η M_i` (so the reachable-set bound is the whole box's)
/// Theorem 2 fails there.
#[test]
fn a_certified_configuration_of_the_paper_vehicle() {
    let mut s = Scenario::paper();
    s.gains.M_p = 1.25;
    let default = default_integral_gains(&s);
    for bandwidth in [1.0, default.bandwidth] {
        let g = IntegralGains {
            bandwidth,
            ..default
        };
        let cert = extended_certificate(&s, &g).unwrap();
        let violated: Vec<_> = cert.violations().map(|c| c.name).collect();
        assert!(violated.is_empty(), "k_eta {bandwidth}: {violated:?}");
    }
    let unlimited = IntegralGains {
        rate: default.level * (2.0 * default.bandwidth),
        ..default
    };
    assert_eq!(unlimited.filtered_rate_bound(), unlimited.rate);
    let fast = extended_certificate(&s, &unlimited).unwrap();
    assert!(fast.violations().any(|c| c.name.starts_with("theorem2")));
}

/// Runs are judged 5 s before their end: the paper's 30 s runs from 25 s as before, a
/// 60 s design's from 55 s.
#[test]
fn convergence_is_judged_on_the_scenarios_horizon() {
    let mut s = Scenario::paper();
    assert_eq!(convergence_of(&s), Convergence::default());
    s.simulation.duration_s = 60.0;
    assert_eq!(convergence_of(&s).after_s, 55.0);
}

/// The case table builds the perturbations it names.
#[test]
fn cases_build_their_perturbations() {
    let s = Scenario::paper();
    let w = s.vehicle.mass_kg * s.vehicle.gravity_m_s2;
    let heavy = CASES[1].plant_scenario(&s);
    assert!((heavy.vehicle.mass_kg - 1.2 * s.vehicle.mass_kg).abs() < 1e-15);
    assert!(heavy.perturbations.is_nominal());
    let all = CASES[COMBINED_CASE].plant_scenario(&s);
    assert!(CASES[COMBINED_CASE].combined && CASES[COMBINED_CASE - 1].combined);
    assert_eq!(CASES[COMBINED_CASE - 1].gust_std_fraction_of_weight, 0.0);
    assert_eq!(all.vehicle.mass_kg, s.vehicle.mass_kg);
    let p = &all.perturbations;
    assert_eq!(p.mass_error_max_fraction, 0.2);
    assert_eq!(p.inertia_error_max_fraction, 0.2);
    assert!((p.force_disturbance_max_N - 0.1 * w).abs() < 1e-15);
    assert!((p.gust_force_std_N - 0.02 * w).abs() < 1e-15);
    assert_eq!(p.gust_time_constant_s, GUST_TIME_CONSTANT_S);
    assert!(CASES[0].plant_scenario(&s) == s);
}

/// A small campaign under a constant force: the integral action removes most of the
/// steady error the paper's law keeps, with no sample outside the extended bounds.
#[test]
fn integral_removes_most_of_a_constant_force_error() {
    let mut s = Scenario::paper();
    s.simulation.precision = Precision::F64;
    let (gains, _) = integral_gains_of(&s);
    let sampler = Sampler::new(&s, SamplerRadii::default()).unwrap();
    let case = Case {
        name: "force",
        force_max_fraction_of_weight: 0.1,
        ..CASES[0]
    };
    // Indices 7.. are the random starts; a few of them.
    let run = |integral, bounds| cell(&s, &case, integral, bounds, &sampler, 3, 10).unwrap();
    let without = run(None, bound_set(&s).unwrap());
    let with = run(Some(&gains), extended_bound_set(&s, &gains).unwrap());
    let p50 = |r: &IntegralRow| r.steady_error_all_mm.p50.unwrap();
    assert!(p50(&without) > 10.0, "{without:?}");
    assert!(p50(&with) < 0.1 * p50(&without), "{with:?} vs {without:?}");
    assert_eq!(with.samples_outside_a_priori, 0);
    assert_eq!(with.refused, 0);
}
