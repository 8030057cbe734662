//! SIL scenario files (TOML): what a software-in-the-loop run flies, holds, senses and is sent.
//!
//! Units are in the key names, unknown keys are refused, and every error names the file, the
//! key and the reason. A scenario file holds:
//!
//! - `flight = "built" | "paper"` (default `"built"`): the firmware's configuration.
//!   `"built"` is `FlightConfig::built()`, the flight file the firmware crate was built with
//!   (`FIRMWARE_FLIGHT_FILE`, default `firmware/flights/x500.toml`), flown on that file's
//!   airframe; `"paper"` is `FlightConfig::paper()` with `allow_uncertified` set (as the
//!   `uncertified-paper` build flies it: its certificate fails and its box does not fit);
//! - `pose_message = "odometry" | "att_pos_mocap"`: the MAVLink message carrying the poses;
//! - optional `control_rate_hz` (the law's rate: 100, 250, 500 or 1000; default: the flight's,
//!   100 Hz unless the firmware was built with another), `motor_time_constant_s` (the lag of
//!   each rotor's speed; default: the flight's airframe's), `plant_mass_factor` (the simulated
//!   body's mass over the flight's, default 1: a payload the firmware does not know of), `hold_s` (held still before the release), `duration_s` (after it), optional `ground_z_m` (flat ground, z up; none if absent) and `pose_outage_s =
//!   [start, end)` (no pose sent; `inf` allowed);
//! - `[initial]`: either `scenario = "paper"`, the `[initial]` state of the paper's scenario
//!   (`host-sim/scenarios/paper.toml`; a file read from disk may also name another scenario
//!   file, relative to itself), or the body at rest at `position_m` (NWU) with attitude
//!   `euler_rad` (roll, pitch, yaw, `R = Rz Ry Rx`; level with yaw 0 if absent);
//! - `[imu]`, `[mocap]`: overrides of single keys of the shared sensor models
//!   ([`SENSORS`], `host-sim/scenarios/sil/sensors.toml`);
//! - `[[commands]]`: ground-station messages, each `at_s` (after the release; negative: during
//!   the hold) and `command` = `"arm"`, `"arm-inverted"`, `"takeoff"` (`height_m` above the
//!   arming point), `"land"`, `"mission-start"`, `"kill"`, `"setpoint"` (`position_m` and
//!   `yaw_rad`, NWU) or `"mission-upload"` (`items`, inline tables of `kind`, `position_m`,
//!   `hold_s`, `yaw_rad`, `acceptance_radius_m`: `scenario_file/mission_items.rs`), built by
//!   [`firmware::ground_station`].

use std::path::Path;

use anyhow::{anyhow, Result};
use firmware::airframe::Airframe;
use firmware::config::FlightConfig;
use firmware::control_rate::ControlRate;
use firmware::ground_station;
use firmware::link::mavlink::dialects::common::MavMessage;
use nalgebra::{UnitQuaternion, Vector3};
use serde::Deserialize;

use super::sensors::{ImuModel, MocapModel, PoseMessage};
use super::setup::SilSetup;
use crate::model::plant::RigidBodyState;
use crate::model::scenario::Scenario;

/// The shared sensor models (`host-sim/scenarios/sil/sensors.toml`, a link to the file the
/// firmware's bench fixtures share: [`flight_files::shared::SENSORS`]), as TOML text.
pub const SENSORS: &str = flight_files::shared::SENSORS;

/// How [`SENSORS`] is named in errors.
const SENSORS_ORIGIN: &str = "host-sim/scenarios/sil/sensors.toml";

/// A whole SIL scenario file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct ScenarioFile {
    #[serde(default)]
    flight: FlightName,
    pose_message: PoseMessageName,
    #[serde(default)]
    control_rate_hz: Option<f64>,
    #[serde(default)]
    motor_time_constant_s: Option<f64>,
    #[serde(default = "unit")]
    plant_mass_factor: f64,
    hold_s: f64,
    duration_s: f64,
    #[serde(default)]
    ground_z_m: Option<f64>,
    #[serde(default)]
    pose_outage_s: Option<[f64; 2]>,
    initial: InitialKeys,
    #[serde(default)]
    imu: ImuKeys,
    #[serde(default)]
    mocap: MocapKeys,
    #[serde(default)]
    commands: Vec<CommandKeys>,
}

/// `flight`: the firmware configuration flown.
#[derive(Clone, Copy, Debug, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
enum FlightName {
    /// `FlightConfig::built()` on `FlightConfig::built_airframe()`.
    #[default]
    Built,
    /// `FlightConfig::paper()` (uncertified, allowed to arm) on `Airframe::paper()`.
    Paper,
}

/// `pose_message`.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(rename_all = "snake_case")]
enum PoseMessageName {
    Odometry,
    AttPosMocap,
}

/// `[initial]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct InitialKeys {
    #[serde(default)]
    scenario: Option<String>,
    #[serde(default)]
    position_m: Option<[f64; 3]>,
    #[serde(default)]
    euler_rad: Option<[f64; 3]>,
}

/// `[imu]` of the sensors file, or single keys of it in a scenario file.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct ImuKeys {
    rate_hz: Option<f64>,
    gyro_noise_rad_s: Option<f64>,
    gyro_bias_rad_s: Option<[f64; 3]>,
    accel_noise_m_s2: Option<f64>,
    accel_bias_m_s2: Option<[f64; 3]>,
}

/// `[mocap]` of the sensors file, or single keys of it in a scenario file.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct MocapKeys {
    rate_hz: Option<f64>,
    latency_s: Option<f64>,
    dropout: Option<f64>,
    position_noise_m: Option<f64>,
    attitude_noise_rad: Option<f64>,
}

/// The sensors file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct SensorsFile {
    imu: ImuKeys,
    mocap: MocapKeys,
}

/// One `[[commands]]` entry.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct CommandKeys {
    at_s: f64,
    command: CommandName,
    #[serde(default)]
    height_m: Option<f32>,
    #[serde(default)]
    position_m: Option<[f32; 3]>,
    #[serde(default)]
    yaw_rad: Option<f32>,
    #[serde(default)]
    items: Option<Vec<mission_items::ItemKeys>>,
}

/// `command`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
enum CommandName {
    Arm,
    ArmInverted,
    Takeoff,
    Land,
    MissionStart,
    Kill,
    Setpoint,
    MissionUpload,
}

fn require<T: Copy>(value: Option<T>, key: &str) -> std::result::Result<T, String> {
    value.ok_or_else(|| format!("{key}: missing"))
}

fn check(ok: bool, key: &str, reason: &str, value: impl std::fmt::Debug) -> Result<(), String> {
    if ok {
        Ok(())
    } else {
        Err(format!("{key}: {reason}, got {value:?}"))
    }
}

fn unit() -> f64 {
    1.0
}

fn positive(key: &str, v: f64) -> Result<(), String> {
    check(v.is_finite() && v > 0.0, key, "must be finite and > 0", v)
}

fn non_negative(key: &str, v: f64) -> Result<(), String> {
    check(v.is_finite() && v >= 0.0, key, "must be finite and >= 0", v)
}

fn finite3<T: Into<f64> + Copy + std::fmt::Debug>(key: &str, a: [T; 3]) -> Result<(), String> {
    check(
        a.iter().all(|x| (*x).into().is_finite()),
        key,
        "must be finite",
        a,
    )
}

impl ImuKeys {
    /// `self` with the keys `over` sets replaced.
    fn overlay(self, over: ImuKeys) -> ImuKeys {
        ImuKeys {
            rate_hz: over.rate_hz.or(self.rate_hz),
            gyro_noise_rad_s: over.gyro_noise_rad_s.or(self.gyro_noise_rad_s),
            gyro_bias_rad_s: over.gyro_bias_rad_s.or(self.gyro_bias_rad_s),
            accel_noise_m_s2: over.accel_noise_m_s2.or(self.accel_noise_m_s2),
            accel_bias_m_s2: over.accel_bias_m_s2.or(self.accel_bias_m_s2),
        }
    }

    fn model(&self) -> Result<ImuModel, String> {
        let m = ImuModel {
            rate_hz: require(self.rate_hz, "imu.rate_hz")?,
            gyro_noise: require(self.gyro_noise_rad_s, "imu.gyro_noise_rad_s")?,
            gyro_bias: require(self.gyro_bias_rad_s, "imu.gyro_bias_rad_s")?,
            accel_noise: require(self.accel_noise_m_s2, "imu.accel_noise_m_s2")?,
            accel_bias: require(self.accel_bias_m_s2, "imu.accel_bias_m_s2")?,
        };
        positive("imu.rate_hz", m.rate_hz)?;
        non_negative("imu.gyro_noise_rad_s", m.gyro_noise)?;
        finite3("imu.gyro_bias_rad_s", m.gyro_bias)?;
        non_negative("imu.accel_noise_m_s2", m.accel_noise)?;
        finite3("imu.accel_bias_m_s2", m.accel_bias)?;
        Ok(m)
    }
}

impl MocapKeys {
    /// `self` with the keys `over` sets replaced.
    fn overlay(self, over: MocapKeys) -> MocapKeys {
        MocapKeys {
            rate_hz: over.rate_hz.or(self.rate_hz),
            latency_s: over.latency_s.or(self.latency_s),
            dropout: over.dropout.or(self.dropout),
            position_noise_m: over.position_noise_m.or(self.position_noise_m),
            attitude_noise_rad: over.attitude_noise_rad.or(self.attitude_noise_rad),
        }
    }

    fn model(&self, message: PoseMessage) -> Result<MocapModel, String> {
        let m = MocapModel {
            rate_hz: require(self.rate_hz, "mocap.rate_hz")?,
            latency_s: require(self.latency_s, "mocap.latency_s")?,
            dropout: require(self.dropout, "mocap.dropout")?,
            position_noise: require(self.position_noise_m, "mocap.position_noise_m")?,
            attitude_noise: require(self.attitude_noise_rad, "mocap.attitude_noise_rad")?,
            message,
        };
        positive("mocap.rate_hz", m.rate_hz)?;
        non_negative("mocap.latency_s", m.latency_s)?;
        check(
            (0.0..=1.0).contains(&m.dropout),
            "mocap.dropout",
            "must be a probability in [0, 1]",
            m.dropout,
        )?;
        non_negative("mocap.position_noise_m", m.position_noise)?;
        non_negative("mocap.attitude_noise_rad", m.attitude_noise)?;
        Ok(m)
    }
}

/// The sensors file's complete models, each key checked.
fn sensors() -> Result<SensorsFile> {
    let s: SensorsFile =
        toml::from_str(SENSORS).map_err(|e| anyhow!("sensor models {SENSORS_ORIGIN}: {e}"))?;
    let both = s
        .imu
        .model()
        .and_then(|_| s.mocap.model(PoseMessage::Odometry));
    both.map_err(|e| anyhow!("sensor models {SENSORS_ORIGIN}: {e}"))?;
    Ok(s)
}

/// Reads the state the body starts from. `dir`: the folder of the scenario file, for a
/// scenario file named relative to it (`None` for embedded text).
fn initial(i: &InitialKeys, dir: Option<&Path>) -> Result<RigidBodyState, String> {
    match (&i.scenario, i.position_m, i.euler_rad) {
        (Some(name), None, None) => {
            if name == "paper" {
                Ok(Scenario::paper().initial_state())
            } else if let Some(dir) = dir {
                Scenario::load(&dir.join(name))
                    .map(|s| s.initial_state())
                    .map_err(|e| format!("initial.scenario: {e:#}"))
            } else {
                Err(format!(
                    "initial.scenario: {name:?} is not \"paper\" (embedded scenarios name no file)"
                ))
            }
        }
        (Some(_), _, _) => Err(
            "initial: give either `scenario` or `position_m` (and `euler_rad`), not both"
                .to_string(),
        ),
        (None, Some(position), euler) => {
            finite3("initial.position_m", position)?;
            let attitude = match euler {
                Some(e) => {
                    finite3("initial.euler_rad", e)?;
                    UnitQuaternion::from_euler_angles(e[0], e[1], e[2])
                }
                None => UnitQuaternion::identity(),
            };
            Ok(RigidBodyState {
                position: Vector3::from(position),
                velocity: Vector3::zeros(),
                attitude,
                angular_velocity: Vector3::zeros(),
            })
        }
        (None, None, _) => Err("initial: missing `scenario` or `position_m`".to_string()),
    }
}

/// The messages of `commands[index]` (one, or a mission upload's count and items).
fn command(index: usize, c: &CommandKeys) -> Result<Vec<(f64, MavMessage)>, String> {
    let key = |k: &str| format!("commands[{index}].{k}");
    check(c.at_s.is_finite(), &key("at_s"), "must be finite", c.at_s)?;
    let takes_height = c.command == CommandName::Takeoff;
    let takes_target = c.command == CommandName::Setpoint;
    let unexpected = [
        ("height_m", c.height_m.is_some() && !takes_height),
        ("position_m", c.position_m.is_some() && !takes_target),
        ("yaw_rad", c.yaw_rad.is_some() && !takes_target),
        (
            "items",
            c.items.is_some() && c.command != CommandName::MissionUpload,
        ),
    ];
    if let Some((k, _)) = unexpected.iter().find(|(_, bad)| *bad) {
        return Err(format!("{}: not a parameter of {:?}", key(k), c.command));
    }
    let message = match c.command {
        CommandName::Arm => ground_station::arm(false),
        CommandName::ArmInverted => ground_station::arm(true),
        CommandName::Takeoff => {
            let h = require(c.height_m, &key("height_m"))?;
            check(
                h.is_finite() && h > 0.0,
                &key("height_m"),
                "must be finite and > 0",
                h,
            )?;
            ground_station::takeoff(h)
        }
        CommandName::Land => ground_station::land(),
        CommandName::MissionStart => ground_station::mission_start(),
        CommandName::Kill => ground_station::kill(),
        CommandName::Setpoint => {
            let p = require(c.position_m, &key("position_m"))?;
            let yaw = require(c.yaw_rad, &key("yaw_rad"))?;
            finite3(&key("position_m"), p)?;
            check(yaw.is_finite(), &key("yaw_rad"), "must be finite", yaw)?;
            ground_station::setpoint_nwu(Vector3::from(p), yaw)
        }
        CommandName::MissionUpload => {
            let items = c.items.as_deref().unwrap_or_default();
            return Ok(mission_items::messages(&key, items)?
                .into_iter()
                .map(|m| (c.at_s, m))
                .collect());
        }
    };
    Ok(vec![(c.at_s, message)])
}

/// Parses the SIL scenario `text` into the run called `name` with `seed`. `origin` names the
/// text in errors; `dir` is the folder of the file it was read from (`None` for embedded
/// text), against which `initial.scenario` paths resolve.
///
/// Errors: `"SIL scenario <origin>: <key>: <reason>"` for a syntax error, an unknown or missing
/// key, a value of the wrong type or out of range; the shared sensor models' own errors name
/// their file.
pub fn parse(
    text: &str,
    origin: &str,
    dir: Option<&Path>,
    name: &str,
    seed: u64,
) -> Result<SilSetup> {
    let file: ScenarioFile =
        toml::from_str(text).map_err(|e| anyhow!("SIL scenario {origin}: {e}"))?;
    let shared = sensors()?;
    build(file, shared, dir, name, seed).map_err(|e| anyhow!("SIL scenario {origin}: {e}"))
}

fn build(
    file: ScenarioFile,
    shared: SensorsFile,
    dir: Option<&Path>,
    name: &str,
    seed: u64,
) -> Result<SilSetup, String> {
    let (mut flight, airframe) = match file.flight {
        FlightName::Built => (FlightConfig::built(), FlightConfig::built_airframe()),
        FlightName::Paper => (
            FlightConfig {
                allow_uncertified: true,
                ..FlightConfig::paper()
            },
            Airframe::paper(),
        ),
    };
    if let Some(hz) = file.control_rate_hz {
        flight.control_rate =
            ControlRate::from_hz(hz).map_err(|e| format!("control_rate_hz: {e}"))?;
    }
    let message = match file.pose_message {
        PoseMessageName::Odometry => PoseMessage::Odometry,
        PoseMessageName::AttPosMocap => PoseMessage::AttPosMocap,
    };
    let imu = shared.imu.overlay(file.imu).model()?;
    let mocap = shared.mocap.overlay(file.mocap).model(message)?;
    let motor_time_constant_s = file
        .motor_time_constant_s
        .unwrap_or(f64::from(airframe.motor_time_constant_s));
    positive("motor_time_constant_s", motor_time_constant_s)?;
    positive("plant_mass_factor", file.plant_mass_factor)?;
    non_negative("hold_s", file.hold_s)?;
    positive("duration_s", file.duration_s)?;
    if let Some(z) = file.ground_z_m {
        check(z.is_finite(), "ground_z_m", "must be finite", z)?;
    }
    if let Some([a, b]) = file.pose_outage_s {
        check(
            a.is_finite() && !b.is_nan() && a <= b,
            "pose_outage_s",
            "must be [start, end) with a finite start <= end",
            [a, b],
        )?;
    }
    let initial = initial(&file.initial, dir)?;
    let commands = file
        .commands
        .iter()
        .enumerate()
        .map(|(i, c)| command(i, c))
        .collect::<Result<Vec<_>, String>>()?
        .into_iter()
        .flatten()
        .collect();
    Ok(SilSetup {
        name: name.to_string(),
        flight,
        imu,
        mocap,
        motor_time_constant_s,
        plant_mass_factor: file.plant_mass_factor,
        initial,
        hold_s: file.hold_s,
        duration_s: file.duration_s,
        commands,
        pose_outage: file.pose_outage_s.map(|[a, b]| (a, b)),
        seed,
        ground_z: file.ground_z_m,
    })
}

mod mission_items;
#[cfg(test)]
mod tests;
