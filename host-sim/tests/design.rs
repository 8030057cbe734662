//! `host-sim design` end to end: the written scenario is re-certified independently (the
//! core's `certify` and the firmware mixer's `set_margin` on the file as read back), it flies, and
//! impossible vehicles are refused with the reason.

use std::path::PathBuf;

use controller_core::{certify, FilterStart, Trajectory};
use firmware::mixer::Mixer;
use host_sim::design::options::LawSearch;
use host_sim::design::variables::AttitudeLaw;
use host_sim::design::{run_design, DesignOptions};
use host_sim::model::scenario::Scenario;

/// The f32 torque set the firmware computes, from the f64 one.
fn f32_set(s: &controller_core::TorqueSet<f64>) -> controller_core::TorqueSet<f32> {
    host_sim::design::certificate::set_f32(s)
}
use host_sim::model::vehicle::{airframe, preset_path, VehicleFile};

fn out_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "host-sim-design-test-{name}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn options(vehicle: PathBuf, out: PathBuf, evaluations: usize) -> DesignOptions {
    DesignOptions {
        vehicle,
        reference: None,
        seed: 3,
        margin: 0.05,
        fit: Default::default(),
        envelope: false,
        vertical: false,
        evaluations,
        duration_s: host_sim::design::options::DEFAULT_DURATION_S,
        law: LawSearch::One(AttitudeLaw::Paper),
        bounds: Default::default(),
        integral: None,
        thrust: host_sim::model::scenario::ThrustKind::Norm,
        position_saturation: Default::default(),
        lemma1: controller_core::Lemma1Form::Tangential,
        speed_limit: None,
        fallback: host_sim::design::options::Fallback::Off,
        out,
    }
}

/// The Crazyflie's design with one option set to `bad` by `set` is refused naming `flag`, and
/// writes nothing.
fn assert_refused_unwritten(flag: &str, bad: f64, set: impl Fn(&mut DesignOptions)) {
    let out = out_dir(&format!("bad{flag}"));
    let mut o = options(preset_path("crazyflie-2.1"), out.clone(), 1);
    set(&mut o);
    let msg = format!("{:#}", run_design(&o).unwrap_err());
    assert!(msg.contains(flag), "{msg}");
    assert!(!out.exists(), "{bad}: wrote {}", out.display());
}

/// The rotor set of a scenario file, through the firmware's own conversion.
fn rotors_of(s: &Scenario) -> firmware::config::RotorConfig {
    let file = VehicleFile {
        vehicle: s.vehicle.clone(),
        rotors: s
            .rotors
            .clone()
            .expect("the design's scenario carries [rotors]"),
        drag: s.drag.clone(),
    };
    airframe(&file).rotors
}

/// The core's `certify` on a written scenario as read back.
fn read_back(s: &Scenario) -> controller_core::Certificate<f64> {
    certify(
        &s.vehicle::<f64>(),
        &s.limits::<f64>(),
        &s.gains::<f64>(),
        &s.trajectory::<f64>().constants(),
        FilterStart::Zero,
    )
    .unwrap()
}

/// [`read_back`]; panics unless every condition holds.
fn certified_read_back(s: &Scenario) -> controller_core::Certificate<f64> {
    let cert = read_back(s);
    assert!(
        cert.require_feasible().is_ok(),
        "{:?}",
        cert.require_feasible()
    );
    cert
}

/// A small-budget design of the Crazyflie: `all_hold` and `fits`, and the written
/// scenario.toml, read back, passes `certify` and the rotor fit of its certified set (with the
/// 5 % margin) on its own.
#[test]
fn design_certifies_and_the_written_scenario_recertifies() {
    let out = out_dir("cf");
    let outcome = run_design(&options(preset_path("crazyflie-2.1"), out.clone(), 16)).unwrap();
    let r = &outcome.report;
    assert!(r.certificate.all_hold && r.rotor_fit.fits && r.rotor_fit.fits_with_margin);
    assert!(r.evaluations <= 16 && r.evaluations > 0);

    let s = Scenario::load(&out.join("scenario.toml")).unwrap();
    let cert = certified_read_back(&s);
    let b = cert.bounds;
    let set = f32_set(&b.torque_set);
    let (t_lo, t_hi) = (b.thrust_min as f32, b.thrust_max as f32);
    let mut rotors = rotors_of(&s);
    let mixer = Mixer::new(&rotors).unwrap();
    assert!(mixer.set_margin(t_lo, t_hi, &set) >= 0.0);
    // The limits written are what the rotors deliver on each axis alone over the certified
    // interval, and the set's per-axis bounds are inside them.
    let alone = mixer.box_fit(t_lo, t_hi, &nalgebra::Vector3::zeros());
    for i in 0..3 {
        assert!((f64::from(alone.torque_capacity[i]) - s.limits.torque_max_Nm[i]).abs() < 1e-6);
        assert!(b.torque_max[i] < s.limits.torque_max_Nm[i]);
    }
    // The margin: the same set fits the range shrunk by 5 % at both ends.
    let span = rotors.thrust_max - rotors.thrust_min;
    rotors.thrust_min += 0.05 * span;
    rotors.thrust_max -= 0.05 * span;
    let shrunk = Mixer::new(&rotors).unwrap();
    assert!(shrunk.set_margin(t_lo, t_hi, &set) >= 0.0);

    // design.json says the same.
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("design.json")).unwrap()).unwrap();
    assert_eq!(json["certificate"]["all_hold"], true);
    assert_eq!(json["rotor_fit"]["fits"], true);
    assert_eq!(json["rotor_fit"]["shape"], "set");
    // Certified with the tangential Lemma 1 (the default), and so is what is read back.
    assert_eq!(json["certificate"]["lemma1"], "tangential");
    assert_eq!(
        s.gains::<f64>().lemma1,
        controller_core::Lemma1Form::Tangential
    );
    let mut paper_gains = s.gains::<f64>();
    paper_gains.lemma1 = controller_core::Lemma1Form::Paper;
    let paper = certify(
        &s.vehicle::<f64>(),
        &s.limits::<f64>(),
        &paper_gains,
        &s.trajectory::<f64>().constants(),
        FilterStart::Zero,
    )
    .unwrap();
    assert!(b.angular_acceleration < paper.bounds.angular_acceleration);
    assert_eq!(
        json["certificate"]["conditions"].as_array().unwrap().len(),
        10
    );
    assert!(json["objective"]["altitude_loss_upside_down_m"].is_number());
    for f in ["design.md", "firmware.toml", "attitude_180.png"] {
        assert!(out.join(f).exists(), "{f} missing");
    }
    // The flight file carries the vehicle file's tables: the firmware's parser reads them.
    let flight = std::fs::read_to_string(out.join("firmware.toml")).unwrap();
    assert!(flight.contains("lemma1 = \"tangential\""), "{flight}");
    VehicleFile::parse_embedded(
        &flight,
        "firmware.toml",
        &["limits", "gains", "trajectory", "design"],
    )
    .unwrap();
    let _ = std::fs::remove_dir_all(&out);
}

/// `--law tilt-priority`: the design's per-axis levels are certified as written (the read-back
/// scenario passes `certify`, tilt priority's band condition included, and the per-axis box fits
/// with the margin), yaw's level is at most roll's, and the firmware's flight file carries the
/// same `[gains.tilt_priority]` table.
#[test]
fn tilt_priority_design_certifies_per_axis_levels() {
    let out = out_dir("tilt");
    let mut o = options(preset_path("hummingbird"), out.clone(), 4);
    o.law = LawSearch::One(AttitudeLaw::TiltPriority);
    let outcome = run_design(&o).unwrap();
    let r = &outcome.report;
    assert!(r.certificate.all_hold && r.rotor_fit.fits && r.rotor_fit.fits_with_margin);
    let s = Scenario::load(&out.join("scenario.toml")).unwrap();
    let gains = s.gains::<f64>();
    let tilt = gains
        .tilt_priority
        .expect("the written scenario flies tilt priority");
    let cert = certified_read_back(&s);
    let band = cert
        .tilt_priority
        .expect("the band condition is part of the certificate");
    assert!(band[0].holds && band[0].lhs > band[0].rhs);
    let b = cert.bounds;
    let levels = b.feedback_torque_axes;
    assert!(
        levels.z <= levels.x * (1.0 + 1e-12) && levels.x == levels.y,
        "{levels:?}"
    );
    for i in 0..3 {
        assert!((levels[i] - r.feedback_torque_axes_Nm[i]).abs() < 1e-9 * levels.x);
    }
    // Body z first: g3 is at least g1 = g2.
    let g = tilt.trace_weights;
    assert!(g.z >= g.x && g.x == g.y, "{g:?}");
    let mut rotors = rotors_of(&s);
    let span = rotors.thrust_max - rotors.thrust_min;
    rotors.thrust_min += 0.05 * span;
    rotors.thrust_max -= 0.05 * span;
    assert!(
        Mixer::new(&rotors).unwrap().set_margin(
            b.thrust_min as f32,
            b.thrust_max as f32,
            &f32_set(&b.torque_set)
        ) >= 0.0
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("design.json")).unwrap()).unwrap();
    assert_eq!(json["law"], "tilt-priority");
    let names: Vec<&str> = json["certificate"]["conditions"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|c| c["name"].as_str())
        .collect();
    assert!(
        names.contains(&"tilt_priority.hysteresis_band"),
        "{names:?}"
    );
    let flight: toml::Table =
        toml::from_str(&std::fs::read_to_string(out.join("firmware.toml")).unwrap()).unwrap();
    let scenario: toml::Table =
        toml::from_str(&std::fs::read_to_string(out.join("scenario.toml")).unwrap()).unwrap();
    assert_eq!(
        flight["gains"]["tilt_priority"], scenario["gains"]["tilt_priority"],
        "the firmware flies the gains that were certified"
    );
    let _ = std::fs::remove_dir_all(&out);
}

/// `--bounds tight` on the x500, whose helix the paper's bounds certify only slowed down: the
/// tight bounds certify a faster one. The written scenario is re-checked with tight bounds
/// computed again at the full budget (Theorem 2 per axis against the rotors' capacity, and the
/// firmware mixer's box fit with the margin), and the firmware file is written only when the
/// paper's certificate, which the firmware re-checks on board, holds too.
#[test]
fn tight_bounds_certify_a_faster_reference_than_the_papers() {
    use host_sim::design::tight::{tight_feedforward, BoundsKind};
    // Both with Lemma 1 as the paper states it: this compares the tight bounds with the paper's.
    let paper_out = out_dir("x500-paper");
    let mut p = options(preset_path("x500"), paper_out.clone(), 1);
    p.lemma1 = controller_core::Lemma1Form::Paper;
    let paper = run_design(&p).unwrap();
    let out = out_dir("x500-tight");
    let mut o = options(preset_path("x500"), out.clone(), 2);
    o.lemma1 = controller_core::Lemma1Form::Paper;
    o.bounds = BoundsKind::Tight;
    let tight = run_design(&o).unwrap();
    let r = &tight.report;
    assert!(r.certificate.all_hold && r.rotor_fit.fits && r.rotor_fit.fits_with_margin);
    assert!(
        r.reference.scale > paper.report.reference.scale,
        "tight {} vs paper {}",
        r.reference.scale,
        paper.report.reference.scale
    );
    // Theorem 2's rows carry the paper's bound beside the tight one, which is below it.
    let theorem2: Vec<_> = r
        .certificate
        .conditions
        .iter()
        .filter(|c| c.name.starts_with("theorem2.torque_max"))
        .collect();
    assert_eq!(theorem2.len(), 3);
    for c in &theorem2 {
        let (paper_rhs, _) = c.paper.expect("the paper's bound beside");
        assert!(c.holds && c.rhs < paper_rhs, "{c:?}");
    }
    assert_eq!(
        out.join("firmware.toml").exists(),
        r.certificate.paper_certified,
        "a flight file only when the firmware's own check passes"
    );

    // Independently: the core's bounds and the tight bounds at the full budget.
    let s = Scenario::load(&out.join("scenario.toml")).unwrap();
    let core = read_back(&s);
    let t = host_sim::bounds::certificate::scenario_tight_bounds(&s).unwrap();
    let split = tight_feedforward(&s.vehicle(), (t.angular_velocity, t.angular_acceleration))
        + core.bounds.feedback_torque_axes;
    let torque = nalgebra::Vector3::from_fn(|i, _| t.torque_max[i].min(split[i]));
    for i in 0..3 {
        assert!(
            torque[i] < s.limits.torque_max_Nm[i],
            "axis {i}: {torque:?} vs {:?}",
            s.limits.torque_max_Nm
        );
    }
    let mut rotors = rotors_of(&s);
    let span = rotors.thrust_max - rotors.thrust_min;
    rotors.thrust_min += 0.05 * span;
    rotors.thrust_max -= 0.05 * span;
    let b = &core.bounds;
    assert!(
        Mixer::new(&rotors)
            .unwrap()
            .box_fit(
                b.thrust_min as f32,
                b.thrust_max as f32,
                &torque.map(|x| x as f32)
            )
            .fits
    );
    let _ = std::fs::remove_dir_all(&out);
    let _ = std::fs::remove_dir_all(&paper_out);
}

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

/// `--duration-s` sets the scoring runs' and the written scenario's length (the default is the
/// paper's 30 s); one shorter than twice the 5 s limit-cycle window is refused, writing nothing.
#[test]
fn duration_sets_the_written_scenario_and_short_ones_are_refused() {
    let out = out_dir("duration");
    let mut o = options(preset_path("crazyflie-2.1"), out.clone(), 1);
    o.duration_s = 12.5;
    let outcome = run_design(&o).unwrap();
    assert_eq!(outcome.report.duration_s, 12.5);
    let s = Scenario::load(&out.join("scenario.toml")).unwrap();
    assert_eq!(s.simulation.duration_s, 12.5);
    let _ = std::fs::remove_dir_all(&out);

    for bad in [9.99, f64::NAN, f64::INFINITY] {
        assert_refused_unwritten("--duration-s", bad, |o| o.duration_s = bad);
    }
}

/// `--speed-limit V`: the design flies and writes the velocity-limited feedback with braking at
/// 0.7 of its `M_p`, in the scenario and the flight file, and the firmware's gains built from
/// the flight file carry it; a limit that is not a positive speed is refused before anything is
/// written.
#[test]
fn speed_limit_is_written_and_bad_ones_are_refused() {
    let out = out_dir("speed-limit");
    let mut o = options(preset_path("crazyflie-2.1"), out.clone(), 1);
    o.speed_limit = Some(4.0);
    let r = run_design(&o).unwrap().report;
    let v = r
        .gains
        .velocity_limit
        .expect("design.json carries the limit");
    assert_eq!(v.speed_m_s, 4.0);
    let share = host_sim::design::variables::BRAKING_SHARE;
    assert!(
        (v.braking_m_s2 - share * r.gains.M_p).abs() < 1e-12,
        "{v:?}"
    );
    let s = Scenario::load(&out.join("scenario.toml")).unwrap();
    let g = s
        .gains::<f64>()
        .velocity_limit
        .expect("scenario.toml carries it");
    assert_eq!((g.speed, g.braking), (v.speed_m_s, v.braking_m_s2));
    let flight = std::fs::read_to_string(out.join("firmware.toml")).unwrap();
    assert!(flight.contains("[gains.velocity_limit]"), "{flight}");
    let _ = std::fs::remove_dir_all(&out);

    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert_refused_unwritten("--speed-limit", bad, |o| o.speed_limit = Some(bad));
    }
    // Not combined with the vertical channel apart (its braking profile is per axis at M_p).
    assert_refused_unwritten("--vertical off", 4.0, |o| {
        o.speed_limit = Some(4.0);
        o.vertical = true;
    });
}

/// The CLI's default path: when no design meets the convergence constraints with the paper's
/// feedback on 30 s runs (the x500 with a one-point budget), `design` designs again with the
/// velocity-limited feedback on 300 s runs (the vertical channel set aside: they are not
/// combined), writes that one and says why in the report; with the fallback off the first design is written as it is.
#[test]
fn unconverged_design_falls_back_to_the_velocity_limit() {
    use host_sim::design::options::{Fallback, FALLBACK_DURATION_S, FALLBACK_SPEED_LIMIT_M_S};
    let out = out_dir("fallback");
    let mut o = options(preset_path("x500"), out.clone(), 1);
    o.fallback = Fallback::VelocityLimited;
    // As the CLI's defaults: the vertical channel apart, which the fallback sets aside.
    o.vertical = true;
    let r = run_design(&o).unwrap().report;
    let why = r.fallback.as_deref().expect("the fallback was taken");
    assert!(why.contains("no design met the convergence"), "{why}");
    assert_eq!(r.duration_s, FALLBACK_DURATION_S);
    let v = r
        .gains
        .velocity_limit
        .expect("the fallback flies the velocity limit");
    assert_eq!(v.speed_m_s, FALLBACK_SPEED_LIMIT_M_S);
    let s = Scenario::load(&out.join("scenario.toml")).unwrap();
    assert_eq!(s.simulation.duration_s, FALLBACK_DURATION_S);
    assert!(s.gains.velocity_limit.is_some());
    let md = std::fs::read_to_string(out.join("design.md")).unwrap();
    assert!(md.contains("**Fallback:**"), "{md}");
    let _ = std::fs::remove_dir_all(&out);

    let out = out_dir("no-fallback");
    let r = run_design(&options(preset_path("x500"), out.clone(), 1))
        .unwrap()
        .report;
    assert!(!r.objective.constraints_met && r.fallback.is_none());
    assert!(r.gains.velocity_limit.is_none());
    let _ = std::fs::remove_dir_all(&out);
}

/// A vehicle whose rotors cannot lift it is refused at once, naming the file, key and reason.
#[test]
fn vehicle_that_cannot_hover_is_refused() {
    let text = std::fs::read_to_string(preset_path("x500"))
        .unwrap()
        .replace("thrust_max_N = 8.54858", "thrust_max_N = 4.0");
    assert!(
        text.contains("thrust_max_N = 4.0"),
        "preset changed; update the test"
    );
    let dir = out_dir("heavy");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("heavy.toml");
    std::fs::write(&file, text).unwrap();
    let e = run_design(&options(file, dir.join("out"), 8)).unwrap_err();
    let msg = format!("{e:#}");
    assert!(
        msg.contains("heavy.toml") && msg.contains("cannot hover"),
        "{msg}"
    );
    assert!(!dir.join("out").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// When the requested reference cannot be certified, the design says which condition binds
/// and certifies the same reference slowed down: its constants are those of the scaled
/// reference, below the requested ones.
#[test]
fn uncertifiable_reference_is_slowed_down_and_said() {
    let out = out_dir("x500");
    let outcome = run_design(&options(preset_path("x500"), out.clone(), 1)).unwrap();
    let r = &outcome.report.reference;
    assert!(r.scaled && r.scale > 0.0 && r.scale < 1.0, "{r:?}");
    assert!(
        r.binding.as_deref().is_some_and(|b| b.contains("iota")),
        "{r:?}"
    );
    let md = std::fs::read_to_string(out.join("design.md")).unwrap();
    assert!(md.contains("CANNOT BE CERTIFIED"));
    let s = Scenario::load(&out.join("scenario.toml")).unwrap();
    let paper = Scenario::paper().trajectory::<f64>().constants();
    let k = s.trajectory::<f64>().constants();
    assert!(k.heading_rate < paper.heading_rate && k.jerk < paper.jerk);
    assert!(outcome.report.certificate.all_hold && outcome.report.rotor_fit.fits);
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
    let flight = std::fs::read_to_string(out.join("firmware.toml")).unwrap();
    assert!(flight.contains("airmode = true"), "{flight}");
    assert!(flight.contains("[gains.vertical]"), "{flight}");
    let _ = std::fs::remove_dir_all(&out);
}
