//! The designs flown: the written scenario as is, the integral action against a mass error, the
//! vertical-priority thrust from upside down, and the command line's defaults (airmode, the local
//! regime, the vertical channel).

use controller_core::{certify, FilterStart, Trajectory};
use firmware::mixer::Mixer;
use host_sim::design::options::LawSearch;
use host_sim::design::run_design;
use host_sim::model::scenario::Scenario;
use host_sim::model::vehicle::preset_path;

use crate::support::{certified_read_back, f32_set, options, out_dir, rotors_of};

/// The written scenario loads and flies as is (the main run's loop), its commands inside the
/// a-priori thrust interval.
#[test]
fn written_scenario_flies() {
    let out = out_dir("fly");
    run_design(&options(preset_path("crazyflie-2.1"), out.clone(), 1)).unwrap();
    let s = Scenario::load(&out.join("scenario.toml")).unwrap();
    let (summary, records) = host_sim::fly::sim::run(&s).unwrap();
    let steps = (s.simulation.duration_s / s.simulation.controller_period_s).round() as usize;
    assert_eq!(records.len(), steps + 1);
    let a = &summary.a_priori;
    for r in &records {
        assert!(
            r.thrust_N >= a.thrust_min_N * (1.0 - 1e-5)
                && r.thrust_N <= a.thrust_max_N * (1.0 + 1e-5)
        );
    }
    let _ = std::fs::remove_dir_all(&out);
}

/// The integral action (`design`'s default): the design carries the bounded integral action sized for a 20 % mass error and
/// a force of 10 % of the weight. The written scenario, read back, passes the extended
/// certificate (the loop's local stability conditions included) and its extended set fits the
/// rotors; the flight file switches it on; and flown from hover with a plant 20 % heavier, it
/// ends within 1 cm, where the same gains without the estimate cannot even hold the weight.
#[test]
fn integral_design_certifies_the_extended_bounds_and_removes_a_mass_error() {
    use host_sim::design::integral::IntegralSpec;
    let out = out_dir("integral");
    let vehicle = preset_path("crazyflie-2.1");
    let mut o = options(vehicle, out.clone(), 4);
    let spec = IntegralSpec::covering(9.81, 0.2, 0.1).unwrap();
    o.integral = Some(spec);
    let r = run_design(&o).unwrap().report;
    assert!(r.certificate.all_hold && r.rotor_fit.fits_with_margin);
    assert_eq!(r.integral, Some(spec));
    let written = r.gains.integral.as_ref().expect("gains.integral written");
    assert_eq!(written.M_i_m_s2, spec.level_m_s2);

    let text = std::fs::read_to_string(out.join("scenario.toml")).unwrap();
    let s = Scenario::parse(&text, "scenario.toml").unwrap();
    let cert = certified_read_back(&s);
    let stability = cert.integral.as_ref().expect("extended certificate");
    assert!(!stability.conditions.is_empty() && stability.conditions.iter().all(|c| c.holds));
    // The extended interval is wider than the paper's for the same gains, and still fits.
    let mut bare = s.gains::<f64>();
    bare.integral = None;
    let paper = certify(
        &s.vehicle::<f64>(),
        &s.limits::<f64>(),
        &bare,
        &s.trajectory::<f64>().constants(),
        FilterStart::Zero,
    )
    .unwrap()
    .bounds;
    let b = cert.bounds;
    assert!(b.thrust_min < paper.thrust_min && b.thrust_max > paper.thrust_max);
    let mixer = Mixer::new(&rotors_of(&s)).unwrap();
    assert!(
        mixer.set_margin(
            b.thrust_min as f32,
            b.thrust_max as f32,
            &f32_set(&b.torque_set)
        ) >= 0.0
    );
    let flight = std::fs::read_to_string(out.join("firmware.toml")).unwrap();
    assert!(flight.contains("[gains.integral]"), "{flight}");
    // The mass error is covered on accelerating references too: the feedforward scale.
    let scale = spec.feedforward_scale().expect("a mass error is covered");
    assert!(scale.level > spec.mass_error_fraction);
    assert_eq!(
        s.gains::<f64>().integral.unwrap().feedforward_scale,
        Some(scale)
    );
    assert!(
        flight.contains("[gains.integral.feedforward_scale]"),
        "{flight}"
    );

    // Hover 2 m up, plant 20 % heavier, 60 s.
    let mut table: toml::Table = text.parse().unwrap();
    let hover: toml::Table = toml::from_str(
        "[trajectory]\nkind = \"hover\"\npoint_m = [0.0, 0.0, 2.0]\n\
         [initial]\nposition_m = [0.0, 0.0, 2.0]\nvelocity_m_s = [0.0, 0.0, 0.0]\n\
         euler_deg = [0.0, 0.0, 0.0]\nangular_velocity_rad_s = [0.0, 0.0, 0.0]\n\
         [perturbations]\nmass_error_fraction = 0.2\n",
    )
    .unwrap();
    table.extend(hover);
    table["simulation"]["duration_s"] = toml::Value::Float(60.0);
    let heavy = Scenario::parse(&table.to_string(), "heavy.toml").unwrap();
    let with = host_sim::fly::sim::run_summary(&heavy).unwrap();
    assert!(with.final_.position_error_m < 0.01, "{:?}", with.final_);
    assert_eq!(with.observed.samples_outside_a_priori_bounds, 0);
    let mut without = heavy.clone();
    without.gains.integral = None;
    let without = host_sim::fly::sim::run_summary(&without).unwrap();
    assert!(
        without.final_.position_error_m > 10.0 * with.final_.position_error_m.max(0.01),
        "without {:?}, with {:?}",
        without.final_,
        with.final_
    );
    let _ = std::fs::remove_dir_all(&out);
}

/// `--thrust vertical-priority`: the design flies and writes the no-dive thrust with the lowest
/// floor its certified box allows. Read back, the scenario's thrust interval is
/// `[T_floor, T_max]`; the firmware mixer's box margin at the floor is the requested one and 1 %
/// below it is not; the flight file carries `[controller]`; and from upside down at hover the
/// same gains lose less altitude with it than with the paper's thrust.
#[test]
fn vertical_priority_design_certifies_its_floor() {
    use host_sim::design::evaluate::upside_down;
    use host_sim::model::scenario::ThrustKind;
    let out = out_dir("vertical-priority");
    let mut o = options(preset_path("crazyflie-2.1"), out.clone(), 4);
    o.thrust = ThrustKind::VerticalPriority;
    let r = run_design(&o).unwrap().report;
    assert!(r.certificate.all_hold && r.certificate.paper_certified);
    let t = &r.thrust;
    assert_eq!(t.mode, "vertical-priority");
    assert!(t.floor_N > 0.0 && t.floor_N <= r.a_priori.0, "{t:?}");
    assert_eq!(t.interval_N, [t.floor_N, r.a_priori.1]);

    let text = std::fs::read_to_string(out.join("scenario.toml")).unwrap();
    let s = Scenario::parse(&text, "scenario.toml").unwrap();
    assert_eq!(s.controller.thrust, ThrustKind::VerticalPriority);
    assert_eq!(s.controller.thrust_floor_N, t.floor_N);
    let c = certified_read_back(&s);
    let b = c.bounds;
    assert_eq!(s.thrust_interval(&c).unwrap(), [t.floor_N, b.thrust_max]);
    let mixer = Mixer::new(&rotors_of(&s)).unwrap();
    let set = f32_set(&b.torque_set);
    let margin = |floor: f64| mixer.set_margin(floor as f32, b.thrust_max as f32, &set);
    assert!(margin(t.floor_N) >= 0.05, "{}", margin(t.floor_N));
    assert!(
        margin(0.99 * t.floor_N) < 0.05,
        "{}",
        margin(0.99 * t.floor_N)
    );
    let flight = std::fs::read_to_string(out.join("firmware.toml")).unwrap();
    assert!(
        flight.contains("[controller]") && flight.contains("thrust = \"vertical-priority\""),
        "{flight}"
    );

    let mut table: toml::Table = text.parse().unwrap();
    let hover: toml::Table =
        toml::from_str("[trajectory]\nkind = \"hover\"\npoint_m = [0.0, 0.0, 2.0]\n").unwrap();
    table.extend(hover);
    let hover = Scenario::parse(&table.to_string(), "hover.toml").unwrap();
    let mut paper = hover.clone();
    paper.controller = Default::default();
    let (with, without) = (
        upside_down(&hover, false).unwrap().altitude_loss_m,
        upside_down(&paper, false).unwrap().altitude_loss_m,
    );
    assert!(with < without, "{with} m with, {without} m without");
    let _ = std::fs::remove_dir_all(&out);
}

/// The command line's defaults (both attitude laws, the norm shape, airmode, the vertical
/// channel apart, the envelope design's local regime, the no-dive thrust and the integral
/// action) on the Crazyflie with a small budget: the written scenario, read back, passes
/// `certify` with the local regime's conditions and the vertical channel; airmode's shadow fit
/// of the certified set and of the local set holds with the 5 % margin on the rotors' own
/// envelope; the report names both laws' objectives and carries the helix tracking of the design
/// and of both baselines.
#[test]
fn default_design_flies_airmode_with_its_local_regime_and_vertical_channel() {
    use host_sim::design::authority::RotorFit;
    let out = out_dir("defaults");
    let mut o = options(preset_path("crazyflie-2.1"), out.clone(), 8);
    o.law = LawSearch::Both;
    o.fit = RotorFit::Airmode;
    o.envelope = true;
    o.vertical = true;
    o.position_saturation = controller_core::PositionSaturation::Norm;
    o.thrust = host_sim::model::scenario::ThrustKind::VerticalPriority;
    o.integral = Some(host_sim::design::integral::IntegralSpec::covering(9.81, 0.1, 0.05).unwrap());
    let r = run_design(&o).unwrap().report;
    assert!(r.certificate.all_hold && r.rotor_fit.fits_with_margin);
    assert_eq!(r.rotor_fit.fit, RotorFit::Airmode);
    assert!(r.rotor_fit.aligned_margin.is_some());
    assert_eq!(r.law_search.len(), 2);
    let tasks = &r.objective.nominal_tasks;
    assert_eq!(tasks.len(), 3);
    for t in tasks {
        let e = t.helix_tracking_error_m.expect("the helix was flown");
        assert!(e.is_finite() && e >= 0.0, "{}: {e}", t.label);
    }

    let s = Scenario::load(&out.join("scenario.toml")).unwrap();
    assert!(s.controller.airmode);
    let g = s.gains::<f64>();
    assert!(
        g.position.vertical.is_some(),
        "the vertical channel was written"
    );
    let cert = certified_read_back(&s);
    let envelope = s
        .airmode_envelope::<f64>()
        .unwrap()
        .expect("airmode carries the rotors' envelope");
    assert!(envelope.shadow_margin(&cert.bounds.torque_set) >= 0.0);
    match (&g.local, &cert.local) {
        (Some(_), Some(local)) => {
            assert!(r.local_regime.is_some());
            assert!(envelope.shadow_margin(&local.torque_set) >= 0.0);
            assert!(local.conditions.iter().all(|c| c.holds));
        }
        (None, None) => assert!(r.local_regime.is_none()),
        (g, c) => panic!("local gains {g:?} but certificate {:?}", c.is_some()),
    }
    // The upside-down loss's split respects what the rotors can do at all: turning the body
    // z axis through 90 degrees from rest takes at least sqrt(pi J / tau) with tau the largest
    // tilting torque (roll and pitch at their limits at once), and stopping the sink rate takes at least v^2 / (2 (T_max / m - g)).
    let o = &r.objective;
    let t = o.upside_down_turn_over.expect("upside down turns over");
    let (v, l) = (s.vehicle::<f64>(), s.limits::<f64>());
    let tilting_torque = l.torque_max.x.hypot(l.torque_max.y);
    let fastest_turn =
        (std::f64::consts::PI * v.inertia.x.min(v.inertia.y) / tilting_torque).sqrt();
    assert!(t.time_s >= fastest_turn, "{t:?} vs {fastest_turn} s");
    let braking_max = l.thrust_max / v.mass - v.gravity;
    let shortest_stop = t.sink_rate_m_s.powi(2) / (2.0 * braking_max);
    let after = o.altitude_loss_upside_down_m - t.altitude_loss_m;
    assert!(
        t.sink_rate_m_s > 0.0 && after >= shortest_stop,
        "{t:?}: {after} m vs {shortest_stop} m"
    );
    let flight = std::fs::read_to_string(out.join("firmware.toml")).unwrap();
    assert!(flight.contains("airmode = true"), "{flight}");
    assert!(flight.contains("[gains.vertical]"), "{flight}");
    let _ = std::fs::remove_dir_all(&out);
}
