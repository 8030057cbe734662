//! Tests of [`super`]: the embedded files parse, defaults, overrides and refusals by key.

use super::*;

const TAKEOFF_LAND: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/scenarios/sil/takeoff-land.toml"
));

/// The error for `text` as file `bad.toml`, with every cause.
fn refused(text: &str) -> String {
    format!(
        "{:#}",
        parse(text, "bad.toml", None, "bad", 1).expect_err("the file must be refused")
    )
}

fn assert_names(e: &str, parts: &[&str]) {
    for p in parts {
        assert!(e.contains(p), "{p:?} missing from: {e}");
    }
}

#[test]
fn the_file_parses() {
    let s = parse(TAKEOFF_LAND, "t.toml", None, "t", 1).unwrap();
    assert_eq!(s.commands.len(), 4);
    assert_eq!(s.ground_z, Some(0.0));
}

#[test]
fn the_law_rate_is_one_of_four() {
    let default = parse(TAKEOFF_LAND, "t.toml", None, "t", 1).unwrap();
    assert_eq!(
        default.flight.control_rate,
        FlightConfig::built().control_rate
    );
    let text = format!("control_rate_hz = 1000\n{TAKEOFF_LAND}");
    let s = parse(&text, "t.toml", None, "t", 1).unwrap();
    assert_eq!(s.flight.control_rate, ControlRate::Hz1000);
    assert_eq!(s.flight.control_period(), 0.001);
    for bad in ["300", "0", "-100", "1e9", "\"fast\""] {
        let e = refused(&format!("control_rate_hz = {bad}\n{TAKEOFF_LAND}"));
        assert_names(&e, &["bad.toml", "control_rate_hz"]);
    }
    let e = refused(&format!("control_rate_hz = 300\n{TAKEOFF_LAND}"));
    assert_names(&e, &["300 Hz", "100, 250, 500 or 1000"]);
}

#[test]
fn unknown_keys_are_named() {
    let e = refused(&TAKEOFF_LAND.replace("hold_s", "hold_time_s"));
    assert_names(&e, &["bad.toml", "hold_time_s"]);
    let e = refused(&format!("{TAKEOFF_LAND}\n[imu]\ngyro_noise = 0.1\n"));
    assert_names(&e, &["bad.toml", "gyro_noise"]);
    let e = refused(&TAKEOFF_LAND.replace("yaw_rad = 1.0", "yaw_deg = 1.0"));
    assert_names(&e, &["bad.toml", "yaw_deg"]);
}

#[test]
fn missing_and_wrong_values_are_named() {
    let e = refused(&TAKEOFF_LAND.replace("duration_s = 50.0", ""));
    assert_names(&e, &["bad.toml", "duration_s"]);
    let e = refused(&TAKEOFF_LAND.replace("duration_s = 50.0", "duration_s = -1.0"));
    assert_names(&e, &["bad.toml", "duration_s", "> 0", "-1"]);
    let e = refused(&TAKEOFF_LAND.replace("hold_s = 1.5", "hold_s = \"long\""));
    assert_names(&e, &["bad.toml", "hold_s"]);
    let e = refused(&TAKEOFF_LAND.replace("\"att_pos_mocap\"", "\"vicon\""));
    assert_names(&e, &["bad.toml", "pose_message", "vicon"]);
    let e = refused(&TAKEOFF_LAND.replace("flight = \"built\"", "flight = \"racer\""));
    assert_names(&e, &["bad.toml", "flight", "racer"]);
    let e = refused(&format!("{TAKEOFF_LAND}\n[mocap]\ndropout = 1.5\n"));
    assert_names(&e, &["bad.toml", "mocap.dropout", "[0, 1]", "1.5"]);
}

#[test]
fn bad_commands_are_named_with_their_index() {
    let e = refused(&TAKEOFF_LAND.replace("command = \"land\"", "command = \"flip\""));
    assert_names(&e, &["bad.toml", "command", "flip"]);
    let e = refused(&TAKEOFF_LAND.replace("height_m = 1.0", ""));
    assert_names(&e, &["bad.toml", "commands[1].height_m", "missing"]);
    let e = refused(&TAKEOFF_LAND.replace("height_m = 1.0", "height_m = -1.0"));
    assert_names(&e, &["bad.toml", "commands[1].height_m", "> 0"]);
    let e =
        refused(&TAKEOFF_LAND.replace("command = \"land\"", "command = \"land\"\nheight_m = 1.0"));
    assert_names(&e, &["bad.toml", "commands[3].height_m", "not a parameter"]);
}

#[test]
fn the_initial_state_is_one_of_two_kinds() {
    let e = refused(&TAKEOFF_LAND.replace("position_m = [0.0, 0.0, 0.0]", ""));
    assert_names(&e, &["bad.toml", "initial", "missing"]);
    let e = refused(&TAKEOFF_LAND.replace(
        "position_m = [0.0, 0.0, 0.0]",
        "position_m = [0.0, 0.0, 0.0]\nscenario = \"paper\"",
    ));
    assert_names(&e, &["bad.toml", "initial", "not both"]);
    let e = refused(&TAKEOFF_LAND.replace(
        "position_m = [0.0, 0.0, 0.0]\neuler_rad = [0.0, 0.0, 0.5]",
        "scenario = \"other.toml\"",
    ));
    assert_names(&e, &["bad.toml", "initial.scenario", "other.toml"]);
}

#[test]
fn overrides_replace_single_sensor_keys() {
    let text = format!("{TAKEOFF_LAND}\n[imu]\nrate_hz = 500.0\n[mocap]\nlatency_s = 0.02\n");
    let s = parse(&text, "o.toml", None, "o", 1).unwrap();
    assert_eq!(s.imu.rate_hz, 500.0);
    assert_eq!(s.imu.gyro_noise, 3e-3);
    assert_eq!(s.mocap.latency_s, 0.02);
    assert_eq!(s.mocap.rate_hz, 100.0);
}

/// `flight` defaults to the built flight file and `motor_time_constant_s` to its
/// airframe's; `flight = "paper"` is the paper's set-up, allowed to arm uncertified, with
/// the paper airframe's time constant; an explicit time constant wins.
#[test]
fn flight_and_motor_lag_default_to_the_built_airframe() {
    let s = parse(TAKEOFF_LAND, "t.toml", None, "t", 1).unwrap();
    assert_eq!(s.flight, FlightConfig::built());
    let tau = FlightConfig::built_airframe().motor_time_constant_s;
    assert_eq!(s.motor_time_constant_s, f64::from(tau));
    let text = TAKEOFF_LAND.replace("flight = \"built\"", "flight = \"paper\"");
    let s = parse(&text, "t.toml", None, "t", 1).unwrap();
    assert!(s.flight.allow_uncertified);
    assert_eq!(s.flight.vehicle, FlightConfig::paper().vehicle);
    assert_eq!(
        s.motor_time_constant_s,
        f64::from(Airframe::paper().motor_time_constant_s)
    );
    let text = TAKEOFF_LAND.replace(
        "flight = \"built\"",
        "flight = \"built\"\nmotor_time_constant_s = 0.05",
    );
    assert_eq!(
        parse(&text, "t.toml", None, "t", 1)
            .unwrap()
            .motor_time_constant_s,
        0.05
    );
}

/// `plant_mass_factor` defaults to 1 (the plant is the flight's); a given one reaches the
/// set-up, and a non-positive or non-finite one is refused with the key.
#[test]
fn plant_mass_factor_defaults_to_the_flight_and_is_checked() {
    assert_eq!(
        parse(TAKEOFF_LAND, "t.toml", None, "t", 1)
            .unwrap()
            .plant_mass_factor,
        1.0
    );
    let with = |v: &str| {
        let text = TAKEOFF_LAND.replace(
            "flight = \"built\"",
            &format!("flight = \"built\"\nplant_mass_factor = {v}"),
        );
        parse(&text, "t.toml", None, "t", 1)
    };
    assert_eq!(with("1.2").unwrap().plant_mass_factor, 1.2);
    for bad in ["0.0", "-1.0", "inf", "nan"] {
        let e = with(bad).unwrap_err().to_string();
        assert!(e.contains("plant_mass_factor"), "{bad}: {e}");
    }
}
