//! The command line's options: `--duration-s` and `--speed-limit` written or refused, the
//! default fallback to the velocity-limited feedback, and a vehicle that cannot hover refused.

use controller_core::Trajectory;
use host_sim::design::run_design;
use host_sim::model::scenario::Scenario;
use host_sim::model::vehicle::preset_path;

use crate::support::{assert_refused_unwritten, options, out_dir};

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
/// 0.7 of its `M_p` (and of `M_up`, `M_down` vertically with the vertical channel apart), in the
/// scenario and the flight file, and the firmware's gains built from the flight file carry it; a
/// limit that is not a positive speed is refused before anything is written.
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

    // With the vertical channel apart, the vertical profile brakes at the same share of each of
    // its levels, written to both files and read back by the scenario's gains.
    let out = out_dir("speed-limit-vertical");
    let mut o = options(preset_path("crazyflie-2.1"), out.clone(), 1);
    o.speed_limit = Some(4.0);
    o.vertical = true;
    let r = run_design(&o).unwrap().report;
    let channel = r.gains.vertical.expect("the vertical channel apart");
    let v = r.gains.velocity_limit.expect("and the velocity limit");
    let (up, down) = v.vertical_braking().expect("the vertical braking");
    assert!((up - share * channel.up_m_s2).abs() < 1e-12, "{v:?}");
    assert!((down - share * channel.down_m_s2).abs() < 1e-12, "{v:?}");
    let s = Scenario::load(&out.join("scenario.toml")).unwrap();
    let b = s
        .gains::<f64>()
        .velocity_limit
        .and_then(|l| l.vertical)
        .expect("scenario.toml carries the vertical braking");
    assert_eq!((b.up, b.down), (up, down));
    let flight = std::fs::read_to_string(out.join("firmware.toml")).unwrap();
    assert!(flight.contains("braking_up_m_s2"), "{flight}");
    let _ = std::fs::remove_dir_all(&out);
}

/// The CLI's default path: when no design meets the convergence constraints with the paper's
/// feedback on 30 s runs (the x500 with a one-point budget), `design` designs again for the same
/// path with the heading held, and when that does not converge either, with the
/// velocity-limited feedback on 300 s runs for the requested reference (with the vertical
/// channel apart, as asked), writes that one and says why in the report, both attempts named;
/// with the fallback off the first design is written as it is.
#[test]
fn unconverged_design_falls_back_to_the_velocity_limit() {
    use host_sim::design::options::{Fallback, DEFAULT_SPEED_LIMIT_M_S, FALLBACK_DURATION_S};
    let out = out_dir("fallback");
    let mut o = options(preset_path("x500"), out.clone(), 1);
    o.fallback = Fallback::VelocityLimited;
    // As the CLI's defaults: the vertical channel apart, which the fallback keeps.
    o.vertical = true;
    let r = run_design(&o).unwrap().report;
    let why = r.fallback.as_deref().expect("the fallback was taken");
    assert!(why.contains("no design met the convergence"), "{why}");
    assert!(
        why.contains("for the same path with the heading held, with"),
        "{why}"
    );
    assert!(r.reference.heading_held.is_none());
    let certified = serde_json::to_value(&r.reference.certified).unwrap();
    assert_eq!(
        certified["heading"]["kind"], "sinusoidal",
        "the 300 s fallback certifies the requested heading: {certified}"
    );
    assert_eq!(r.duration_s, FALLBACK_DURATION_S);
    let v = r
        .gains
        .velocity_limit
        .expect("the fallback flies the velocity limit");
    assert_eq!(v.speed_m_s, DEFAULT_SPEED_LIMIT_M_S);
    assert!(
        r.gains.vertical.is_some() && v.vertical_braking().is_some(),
        "{v:?}"
    );
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

/// Given the fallback's first step (the requested path with the heading held, here asked for
/// directly on the Crazyflie with a one-point budget), when it designs, then it certifies the
/// paper's helix with a constant heading at the helix's initial one, reports the requested
/// swinging heading and why it was held (design.json and design.md), and writes the held
/// heading into the scenario it flies.
#[test]
fn the_heading_held_design_certifies_the_same_path_at_a_constant_heading() {
    let out = out_dir("heading-held");
    let mut o = options(preset_path("crazyflie-2.1"), out.clone(), 1);
    o.heading_held = Some("(the first attempt's outcome)".to_owned());
    let r = run_design(&o).unwrap().report;
    assert_eq!(
        r.reference.heading_held.as_deref(),
        Some("(the first attempt's outcome)")
    );
    let requested = serde_json::to_value(&r.reference.requested).unwrap();
    let certified = serde_json::to_value(&r.reference.certified).unwrap();
    assert_eq!(requested["heading"]["kind"], "sinusoidal", "{requested}");
    assert_eq!(certified["heading"]["kind"], "constant", "{certified}");
    // The same path: everything but the heading.
    for key in [
        "kind",
        "center_m",
        "radius_m",
        "vertical_amplitude_m",
        "frequency_rad_s",
    ] {
        assert_eq!(certified[key], requested[key], "{key}");
    }
    let s = Scenario::load(&out.join("scenario.toml")).unwrap();
    let reference = s.trajectory::<f64>();
    let yaw = |t: f64| {
        let h = reference.sample(t).heading;
        h.y.atan2(h.x)
    };
    // Held at ψ_d(0) of the paper's helix, whose heading swings ±π about 0.
    for t in [0.0, 3.0, 7.5, 12.0] {
        assert!(yaw(t).abs() < 1e-12, "{t}: {}", yaw(t));
    }
    let md = std::fs::read_to_string(out.join("design.md")).unwrap();
    assert!(
        md.contains("**Heading held:** for the requested reference (the first"),
        "{md}"
    );
    assert!(!md.contains("certified as is"), "{md}");
    let json = std::fs::read_to_string(out.join("design.json")).unwrap();
    assert!(json.contains("\"heading_held\""));
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
