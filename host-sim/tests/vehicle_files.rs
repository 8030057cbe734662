//! The vehicle files: every preset parses, validates, builds the firmware's mixer, hovers and
//! has the mixer's yaw sign convention; `paper.toml` is the paper airframe the firmware flies;
//! bad files are refused with file, key and reason.

use controller_core::Vehicle;
use firmware::airframe::Airframe;
use firmware::config::FlightConfig;
use firmware::mixer::Mixer;
use host_sim::model::scenario::Scenario;
use host_sim::model::vehicle::{self, VehicleFile, PRESETS};
use nalgebra::Vector3;

fn preset(name: &str) -> (String, VehicleFile) {
    let path = vehicle::preset_path(name);
    let file = vehicle::load(&path).unwrap_or_else(|e| panic!("{e:#}"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{e}"));
    (text, file)
}

/// The spins as written in the file's `spin = [...]` line, read from the text (not through the
/// parser): `true` for "cw".
fn written_cw(text: &str) -> Vec<bool> {
    let line = text
        .lines()
        .find(|l| l.trim_start().starts_with("spin ="))
        .unwrap_or_else(|| panic!("no spin line"));
    let list = line.split('[').nth(1).and_then(|r| r.split(']').next());
    list.unwrap_or_else(|| panic!("bad spin line {line}"))
        .split(',')
        .map(|s| s.trim().trim_matches('"'))
        .map(|s| match s {
            "cw" => true,
            "ccw" => false,
            other => panic!("spin {other}"),
        })
        .collect()
}

/// Every preset parses with every key present (all keys are required, so this also checks the
/// parser's key lists against the serde tables: a key in one and not the other is refused),
/// validates, and its geometry gives the firmware's mixer.
#[test]
fn every_preset_parses_and_builds_the_mixer() {
    for name in PRESETS {
        let (_, file) = preset(name);
        assert_eq!(file.vehicle.name.as_deref(), Some(name));
        let airframe = vehicle::airframe(&file);
        assert_eq!(airframe.name, name);
        assert!(!airframe.source.is_empty());
        assert_eq!(airframe.real_propeller, name != "paper");
        Mixer::new(&airframe.rotors).unwrap_or_else(|e| panic!("{name}: {e:?}"));
    }
}

/// Each preset can hover: four rotors at full thrust exceed the weight (computed here from the
/// parsed values), with room to spare for control.
#[test]
fn every_preset_hovers() {
    for name in PRESETS {
        let (_, file) = preset(name);
        let weight = file.vehicle.mass_kg * file.vehicle.gravity_m_s2;
        let most = 4.0 * file.rotors.thrust_max_N;
        assert!(most > 1.2 * weight, "{name}: {most} N vs weight {weight} N");
        // And the mixer, at the hover thrust with no torque, stays inside each rotor's range.
        let airframe = vehicle::airframe(&file);
        let mixer = Mixer::new(&airframe.rotors).unwrap_or_else(|e| panic!("{e:?}"));
        let out = mixer.mix(weight as f32, &Vector3::zeros());
        assert!(!out.saturated(), "{name}: {out:?}");
        for f in out.thrust.iter() {
            assert!(
                (f - weight as f32 / 4.0).abs() < 1e-4 * weight as f32,
                "{name}: {f}"
            );
        }
    }
}

/// The mixer's signs on each preset, against the geometry and spins as written in the file: +τx
/// (roll right wing down, FLU) is made by the left rotors (y > 0), +τy (nose down) by the rear
/// ones (x < 0), +τz (counter-clockwise seen from above) by the clockwise rotors, whose
/// reaction torque is counter-clockwise.
#[test]
fn every_preset_has_the_mixer_sign_convention() {
    for name in PRESETS {
        let (text, file) = preset(name);
        let cw = written_cw(&text);
        let airframe = vehicle::airframe(&file);
        let mixer = Mixer::new(&airframe.rotors).unwrap_or_else(|e| panic!("{e:?}"));
        let hover = (file.vehicle.mass_kg * file.vehicle.gravity_m_s2) as f32;
        let small = 0.01 * hover * airframe.rotors.arm_length;
        let yaw_small = 0.01 * hover * airframe.rotors.torque_per_thrust();
        let p = &file.rotors.positions_m;
        let left: Vec<bool> = p.iter().map(|q| q[1] > 0.0).collect();
        let rear: Vec<bool> = p.iter().map(|q| q[0] < 0.0).collect();
        let cases = [
            (Vector3::new(small, 0.0, 0.0), left),
            (Vector3::new(0.0, small, 0.0), rear),
            (Vector3::new(0.0, 0.0, yaw_small), cw),
        ];
        for (tau, more) in cases {
            let out = mixer.mix(hover, &tau);
            assert!(!out.saturated(), "{name}: {out:?}");
            let base = hover / 4.0;
            for (k, (f, expected)) in out.thrust.iter().zip(&more).enumerate() {
                assert_eq!(*f > base, *expected, "{name}: tau {tau}, rotor {k}");
            }
        }
    }
}

/// `paper.toml` describes the airframe the firmware's paper configuration flies, value for value.
#[test]
fn paper_file_is_the_paper_airframe() {
    let (_, file) = preset("paper");
    let airframe = vehicle::airframe(&file);
    assert_eq!(airframe, Airframe::paper());
    let config = FlightConfig::paper();
    assert_eq!(airframe.vehicle, config.vehicle);
    assert_eq!(airframe.rotors, config.rotors);
    assert_eq!(airframe.vehicle, Vehicle::paper());
    // The scenario's rigid body is the same too.
    let scenario = Scenario::paper();
    assert_eq!(file.vehicle.mass_kg, scenario.vehicle.mass_kg);
    assert_eq!(file.vehicle.inertia_kg_m2, scenario.vehicle.inertia_kg_m2);
    assert_eq!(file.vehicle.gravity_m_s2, scenario.vehicle.gravity_m_s2);
}

/// The generated firmware source carries every f32 value of the airframe, printed so it reads
/// back to the same bits.
#[test]
fn rust_source_carries_the_airframe_values() {
    for name in PRESETS {
        let (_, file) = preset(name);
        let a = vehicle::airframe(&file);
        let src = file.to_rust_source();
        assert!(src.starts_with("crate::airframe::Airframe {"), "{src}");
        assert_eq!(src.matches('{').count(), src.matches('}').count(), "{src}");
        let r = &a.rotors;
        let mut values = vec![
            a.vehicle.mass,
            a.vehicle.gravity,
            r.thrust_min,
            r.thrust_max,
            r.torque_per_thrust(),
            r.curve_factor,
            r.throttle_idle,
            r.arm_length,
            a.motor_time_constant_s,
        ];
        values.extend(a.vehicle.inertia.iter());
        values.extend(a.body_drag);
        values.extend(r.rotors.iter().flat_map(|x| x.position));
        for v in values {
            let text = format!("{v:?}f32");
            assert!(src.contains(&text), "{name}: {text} not in\n{src}");
            let back: f32 = format!("{v:?}").parse().unwrap_or(f32::NAN);
            assert_eq!(back.to_bits(), v.to_bits());
        }
        assert!(src.contains(&format!("name: {:?}", a.name)));
    }
}

/// One bad edit of a preset and what the error must name.
struct Bad {
    /// Text replaced (must occur in x500.toml) ...
    from: &'static str,
    /// ... by this.
    to: &'static str,
    /// The key the error must name.
    key: &'static str,
    /// A word of the reason.
    reason: &'static str,
}

/// Missing, negative, zero, non-finite and unknown keys, wrong types and impossible vehicles are
/// refused, each with the file, the key and the reason.
#[test]
fn bad_vehicle_files_are_refused_with_file_key_and_reason() {
    let (text, _) = preset("x500");
    let bad = [
        Bad {
            from: "mass_kg = 2.0643076923076924",
            to: "",
            key: "vehicle.mass_kg",
            reason: "missing",
        },
        Bad {
            from: "mass_kg = 2.0643076923076924",
            to: "mass_kg = -2.0",
            key: "vehicle.mass_kg",
            reason: "negative",
        },
        Bad {
            from: "mass_kg = 2.0643076923076924",
            to: "mass_kg = 0.0",
            key: "vehicle.mass_kg",
            reason: "> 0",
        },
        Bad {
            from: "mass_kg = 2.0643076923076924",
            to: "mass_kg = 1e300",
            key: "vehicle.mass_kg",
            reason: "f32 range",
        },
        Bad {
            from: "mass_kg = 2.0643076923076924",
            to: "mass_kg = nan",
            key: "vehicle.mass_kg",
            reason: "finite",
        },
        Bad {
            from: "mass_kg = 2.0643076923076924",
            to: "mass_kg = \"heavy\"",
            key: "vehicle.mass_kg",
            reason: "invalid type",
        },
        Bad {
            from: "mass_kg = 2.0643076923076924",
            to: "mass_kgs = 2.0",
            key: "vehicle.mass_kgs",
            reason: "unknown key",
        },
        Bad {
            from: "gravity_m_s2 = 9.8 ",
            to: "gravity_m_s2 = inf ",
            key: "vehicle.gravity_m_s2",
            reason: "finite",
        },
        Bad {
            from: "0.0238909430827317, 0.0238909430827317,",
            to: "0.0238909430827317, -0.0238909430827317,",
            key: "vehicle.inertia_kg_m2[1]",
            reason: "negative",
        },
        Bad {
            from: "thrust_max_N = 8.54858 ",
            to: "thrust_max_N = -inf ",
            key: "rotors.thrust_max_N",
            reason: "finite",
        },
        Bad {
            from: "thrust_min_N = 0.19234305",
            to: "thrust_min_N = 9.0",
            key: "rotors.thrust_max_N",
            reason: "thrust range empty",
        },
        Bad {
            from: "thrust_max_N = 8.54858 ",
            to: "thrust_max_N = 4.0 ",
            key: "rotors.thrust_max_N",
            reason: "cannot hover",
        },
        Bad {
            from: "motor_time_constant_s = 0.025",
            to: "motor_time_constant_s = 0.0",
            key: "rotors.motor_time_constant_s",
            reason: "> 0",
        },
        Bad {
            from: "yaw_torque_per_thrust_m = 0.016",
            to: "",
            key: "rotors.yaw_torque_per_thrust_m",
            reason: "missing",
        },
        Bad {
            from: "spin = [\"ccw\", \"ccw\", \"cw\", \"cw\"]",
            to: "spin = [\"ccw\", \"ccw\", \"ccw\", \"cw\"]",
            key: "rotors.spin",
            reason: "two",
        },
        Bad {
            from: "spin = [\"ccw\", \"ccw\", \"cw\", \"cw\"]",
            to: "spin = [\"ccw\", \"ccw\", \"cw\"]",
            key: "rotors.spin",
            reason: "3 spins",
        },
        Bad {
            from: "spin = [\"ccw\", \"ccw\", \"cw\", \"cw\"]",
            to: "spin = [\"ccw\", \"up\", \"cw\", \"cw\"]",
            key: "rotors.spin",
            reason: "unknown variant",
        },
        Bad {
            from: "[-0.174, -0.174],   # rotor_3: rear-right",
            to: "[-0.174, -0.174], [0.3, 0.0],",
            key: "rotors.positions_m",
            reason: "5 rotors",
        },
        Bad {
            from: "[-0.174, -0.174],   # rotor_3: rear-right",
            to: "[0.174, 0.174],",
            key: "rotors.positions_m",
            reason: "singular geometry",
        },
        Bad {
            from: "thrust_curve_factor = 0.7391304347826086",
            to: "thrust_curve_factor = 1.5",
            key: "rotors.thrust_curve_factor",
            reason: "[0, 1]",
        },
        Bad {
            from: "throttle_idle = 0.0",
            to: "throttle_idle = 1.0",
            key: "rotors.throttle_idle",
            reason: "[0, 1)",
        },
        Bad {
            from: "real_propeller = true",
            to: "",
            key: "vehicle.real_propeller",
            reason: "missing",
        },
        Bad {
            from: "[rotors]",
            to: "[rotor]",
            key: "rotor",
            reason: "unknown key",
        },
    ];
    let mut tried = 0;
    for b in &bad {
        assert!(text.contains(b.from), "{} not in x500.toml", b.from);
        let edited = text.replacen(b.from, b.to, 1);
        let e = VehicleFile::parse(&edited, "edited-x500.toml")
            .map(|_| ())
            .expect_err(&format!("{} -> {} accepted", b.from, b.to));
        let shown = e.to_string();
        assert_eq!(e.file, "edited-x500.toml", "{shown}");
        assert_eq!(e.key, b.key, "{shown}");
        assert!(e.reason.contains(b.reason), "{shown}");
        assert!(
            shown.starts_with(&format!("edited-x500.toml: {}: ", b.key)),
            "{shown}"
        );
        tried += 1;
    }
    assert!(tried >= 20);
    // A body drag table is optional; a bad one is refused.
    let with_drag = format!("{text}\n[drag]\nbody_drag_N_s2_m2 = [0.01, -0.01, 0.0]\n");
    let e = VehicleFile::parse(&with_drag, "d.toml")
        .map(|_| ())
        .expect_err("negative drag");
    assert_eq!(e.key, "drag.body_drag_N_s2_m2[1]", "{e}");
    // And a file that is not there is named too.
    let e = vehicle::load(std::path::Path::new("no/such/vehicle.toml")).map(|_| ());
    let e = e.expect_err("missing file").to_string();
    assert!(e.contains("no/such/vehicle.toml"), "{e}");
}

/// Found by the `vehicle_toml` fuzz target (tests/fuzz/regressions/vehicle_toml/): a rotor
/// position finite in f64 but beyond f32 (-2.2e113 m) was accepted, and the firmware's flight
/// values held `-inf` and an infinite arm length. So is one whose coordinates fit f32 but whose
/// distance from the centre (the arm length) does not. Both are refused now.
#[test]
fn rotor_positions_beyond_f32_are_refused() {
    let (text, _) = preset("x500");
    let rear_right = "[-0.174, -0.174],   # rotor_3";
    assert!(text.contains(rear_right));
    for position in [
        "[-222222222222222222222222222222222222222222222222222222222222222222222222222222222222222222222222222222222222222220.174, -0.174],",
        "[3e38, -3e38],",
    ] {
        let edited = text.replacen(rear_right, &format!("{position}   # rotor_3"), 1);
        let e = VehicleFile::parse(&edited, "x.toml")
            .map(|_| ())
            .expect_err(position);
        assert_eq!(e.key, "rotors.positions_m[3]", "{e}");
        assert!(e.reason.contains("f32 range"), "{e}");
    }
}

/// A scenario can carry a vehicle's `[rotors]` and `[drag]`; the paper scenario does not, so its
/// serialisation is unchanged; `with_vehicle` swaps the vehicle and the result is a valid
/// scenario file again; a scenario's bad `[rotors]` is refused with its key.
#[test]
fn scenario_carries_vehicle_tables() {
    let paper = Scenario::paper();
    assert!(paper.rotors.is_none() && paper.drag.is_none());
    let text = toml::to_string(&paper).unwrap_or_else(|e| panic!("{e}"));
    assert!(!text.contains("rotors") && !text.contains("drag") && !text.contains("name"));
    let (_, hb) = preset("hummingbird");
    let s = paper.with_vehicle(&hb);
    assert_eq!(s.vehicle, hb.vehicle);
    assert_eq!(s.rotors.as_ref(), Some(&hb.rotors));
    assert_eq!(s.drag, hb.drag);
    assert_eq!(s.gains, paper.gains);
    let text = toml::to_string(&s).unwrap_or_else(|e| panic!("{e}"));
    let back = Scenario::parse(&text, "swapped.toml").unwrap_or_else(|e| panic!("{e:#}"));
    assert_eq!(back, s);
    let p = s
        .rotor_config()
        .unwrap_or_else(|| panic!("the swapped scenario has [rotors]"));
    assert_eq!(p.body_drag_N_s2_m2, [0.5e-2, 0.5e-2, 1e-2]);
    assert_eq!(p.rotors.rotors.map(|r| r.spin), [-1.0, 1.0, -1.0, 1.0]);
    assert_eq!(p.motor_time_constant_s, 0.005);
    assert_eq!(s.plant().mass, 0.5);
    let bad = text.replacen(
        "motor_time_constant_s = 0.005",
        "motor_time_constant_s = -1.0",
        1,
    );
    assert_ne!(bad, text);
    let e = Scenario::parse(&bad, "s.toml")
        .map(|_| ())
        .expect_err("negative tau");
    let e = format!("{e:#}");
    assert!(
        e.contains("s.toml") && e.contains("rotors.motor_time_constant_s"),
        "{e}"
    );
}

/// A vehicle's tables inside a larger file (a flight or scenario file) parse when the other
/// tables are named, and a table named nowhere is still refused.
#[test]
fn vehicle_tables_embedded_in_a_larger_file() {
    let (text, file) = preset("crazyflie-2.1");
    let larger = format!("{text}\n[limits]\nthrust_max_N = 0.5\n\n[design]\nseed = 3\n");
    let embedded = VehicleFile::parse_embedded(&larger, "flight.toml", &["limits", "design"])
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(embedded, file);
    let e = VehicleFile::parse_embedded(&larger, "flight.toml", &["limits"])
        .map(|_| ())
        .expect_err("[design] not named");
    assert_eq!(
        (e.file.as_str(), e.key.as_str()),
        ("flight.toml", "design"),
        "{e}"
    );
    assert!(e.reason.contains("unknown key"), "{e}");
    let bad = larger.replacen(
        "motor_time_constant_s = 0.072",
        "motor_time_constant_s = \"slow\"",
        1,
    );
    let e = VehicleFile::parse_embedded(&bad, "flight.toml", &["limits", "design"])
        .map(|_| ())
        .expect_err("wrong type");
    assert_eq!(e.key, "rotors.motor_time_constant_s", "{e}");
}
