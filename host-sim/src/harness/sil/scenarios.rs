//! The software-in-the-loop scenarios: the files in `host-sim/scenarios/sil/` (embedded, so a
//! name works from any folder), or a scenario file read from a path. The format is
//! [`super::scenario_file`]'s; the ground-station messages they send are
//! [`firmware::ground_station`]'s.

use std::path::Path;

use anyhow::{anyhow, Context, Result};

use super::scenario_file;
use super::setup::SilSetup;

/// The scenario names the CLI accepts.
pub const NAMES: [&str; 6] = [
    "paper",
    "pose-loss",
    "takeoff-land",
    "helix",
    "mission",
    "ground",
];

/// The embedded scenario files, by name (same order as [`NAMES`]).
const FILES: [&str; 6] = [
    include_str!(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenarios/sil/paper.toml"
    )),
    include_str!(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenarios/sil/pose-loss.toml"
    )),
    include_str!(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenarios/sil/takeoff-land.toml"
    )),
    include_str!(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenarios/sil/helix.toml"
    )),
    include_str!(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenarios/sil/mission.toml"
    )),
    include_str!(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenarios/sil/ground.toml"
    )),
];

/// The embedded scenario `name` with `seed`, `None` if there is no such scenario (see
/// [`NAMES`]).
pub fn by_name(name: &str, seed: u64) -> Option<SilSetup> {
    let i = NAMES.iter().position(|n| *n == name)?;
    let origin = format!("host-sim/scenarios/sil/{name}.toml");
    Some(
        scenario_file::parse(FILES[i], &origin, None, name, seed)
            .unwrap_or_else(|e| unreachable!("embedded SIL scenario is valid: {e:#}")),
    )
}

/// The scenario `name_or_path` with `seed`: an embedded scenario by name (see [`NAMES`]), or
/// else a scenario file (its name is the file's stem).
///
/// Errors: neither a name nor a readable file; the file is refused (file, key and reason).
pub fn load(name_or_path: &str, seed: u64) -> Result<SilSetup> {
    if let Some(setup) = by_name(name_or_path, seed) {
        return Ok(setup);
    }
    let path = Path::new(name_or_path);
    if !path.is_file() {
        return Err(anyhow!(
            "unknown SIL scenario {name_or_path:?}; known: {}, or the path of a scenario file",
            NAMES.join(", ")
        ));
    }
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("cannot read SIL scenario file {}", path.display()))?;
    let name = path
        .file_stem()
        .map_or_else(|| "sil".into(), |s| s.to_string_lossy().into_owned());
    scenario_file::parse(
        &text,
        &path.display().to_string(),
        path.parent(),
        &name,
        seed,
    )
}

/// Scenario `paper` (`host-sim/scenarios/sil/paper.toml`): the paper's Section VI manoeuvre on
/// the built vehicle (`FlightConfig::built()`): released upside down 4.1 m from the demo
/// mission's start, held still 1.5 s for calibration, then released while the ground station
/// sends an explicit upside-down arm and the mission; 30 s with realistic sensors.
pub fn paper(seed: u64) -> SilSetup {
    embedded(0, seed)
}

/// Scenario `pose-loss` (`host-sim/scenarios/sil/pose-loss.toml`): hand launch level at 2 m,
/// take off to 2.5 m, hover; the pose stops at 6 s.
pub fn pose_loss(seed: u64) -> SilSetup {
    embedded(1, seed)
}

/// Scenario `takeoff-land` (`host-sim/scenarios/sil/takeoff-land.toml`): takeoff from the
/// ground to 1 m, a hover target, landing and the automatic disarm.
pub fn takeoff_land(seed: u64) -> SilSetup {
    embedded(2, seed)
}

/// Scenario `helix` (`host-sim/scenarios/sil/helix.toml`): the built flight's demo mission
/// from an upright start 4.1 m away with a 100° heading error; 60 s.
pub fn helix(seed: u64) -> SilSetup {
    embedded(3, seed)
}

fn embedded(i: usize, seed: u64) -> SilSetup {
    by_name(NAMES[i], seed).unwrap_or_else(|| unreachable!("NAMES[{i}] is embedded"))
}

#[cfg(test)]
mod tests {
    //! The files against the Rust set-ups they replace (kept here verbatim as the independent
    //! computation): every field, every message, bit for bit (`Debug` prints floats exactly).

    use firmware::config::FlightConfig;
    use firmware::frames;
    use firmware::link::mavlink::dialects::common::{
        MavCmd, MavFrame, MavMessage, PositionTargetTypemask, COMMAND_LONG_DATA,
        SET_POSITION_TARGET_LOCAL_NED_DATA,
    };
    use nalgebra::{UnitQuaternion, Vector3};

    use super::super::sensors::{ImuModel, MocapModel, PoseMessage};
    use super::super::setup::SilSetup;
    use super::*;
    use crate::model::plant::RigidBodyState;
    use crate::model::scenario::Scenario;

    fn command(command: MavCmd, p1: f32, p2: f32, p7: f32) -> MavMessage {
        MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
            param1: p1,
            param2: p2,
            param7: p7,
            command,
            target_system: 1,
            target_component: 1,
            ..Default::default()
        })
    }

    fn arm(inverted: bool) -> MavMessage {
        command(
            MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
            1.0,
            if inverted { 2989.0 } else { 0.0 },
            0.0,
        )
    }

    fn takeoff(height: f32) -> MavMessage {
        command(MavCmd::MAV_CMD_NAV_TAKEOFF, 0.0, 0.0, height)
    }

    fn land() -> MavMessage {
        command(MavCmd::MAV_CMD_NAV_LAND, 0.0, 0.0, 0.0)
    }

    fn mission_start() -> MavMessage {
        command(MavCmd::MAV_CMD_MISSION_START, 0.0, 0.0, 0.0)
    }

    fn kill() -> MavMessage {
        command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 0.0, 21196.0, 0.0)
    }

    fn setpoint_nwu(position: Vector3<f32>, yaw: f32) -> MavMessage {
        let [x, y, z] = frames::flip_to_array(&position);
        MavMessage::SET_POSITION_TARGET_LOCAL_NED(SET_POSITION_TARGET_LOCAL_NED_DATA {
            x,
            y,
            z,
            yaw: frames::flip_yaw(yaw),
            type_mask: PositionTargetTypemask::POSITION_TARGET_TYPEMASK_VX_IGNORE
                | PositionTargetTypemask::POSITION_TARGET_TYPEMASK_VY_IGNORE
                | PositionTargetTypemask::POSITION_TARGET_TYPEMASK_VZ_IGNORE
                | PositionTargetTypemask::POSITION_TARGET_TYPEMASK_AX_IGNORE
                | PositionTargetTypemask::POSITION_TARGET_TYPEMASK_AY_IGNORE
                | PositionTargetTypemask::POSITION_TARGET_TYPEMASK_AZ_IGNORE
                | PositionTargetTypemask::POSITION_TARGET_TYPEMASK_YAW_RATE_IGNORE,
            target_system: 1,
            target_component: 1,
            coordinate_frame: MavFrame::MAV_FRAME_LOCAL_NED,
            ..Default::default()
        })
    }

    fn imu() -> ImuModel {
        ImuModel {
            rate_hz: 1000.0,
            gyro_noise: 3e-3,
            gyro_bias: [0.01, -0.02, 0.015],
            accel_noise: 0.05,
            accel_bias: [0.05, -0.03, 0.08],
        }
    }

    fn mocap(message: PoseMessage) -> MocapModel {
        MocapModel {
            rate_hz: 100.0,
            latency_s: 0.010,
            dropout: 0.02,
            position_noise: 5e-4,
            attitude_noise: 2e-3,
            message,
        }
    }

    fn at_rest(position: Vector3<f64>, attitude: UnitQuaternion<f64>) -> RigidBodyState {
        RigidBodyState {
            position,
            velocity: Vector3::zeros(),
            attitude,
            angular_velocity: Vector3::zeros(),
        }
    }

    /// The built flight's motor time constant \[s\] (what the files leave to the airframe).
    fn built_tau() -> f64 {
        f64::from(FlightConfig::built_airframe().motor_time_constant_s)
    }

    fn old_paper(seed: u64) -> SilSetup {
        SilSetup {
            name: "paper".into(),
            flight: FlightConfig::built(),
            imu: imu(),
            mocap: mocap(PoseMessage::Odometry),
            motor_time_constant_s: built_tau(),
            plant_mass_factor: 1.0,
            initial: at_rest(
                Vector3::new(3.0, 2.0, 6.0),
                UnitQuaternion::from_euler_angles(
                    (-179.0f64).to_radians(),
                    0.0,
                    100.0f64.to_radians(),
                ),
            ),
            hold_s: 1.5,
            duration_s: 30.0,
            commands: vec![(0.0, arm(true)), (0.0, mission_start())],
            pose_outage: None,
            seed,
            ground_z: None,
        }
    }

    fn old_helix(seed: u64) -> SilSetup {
        SilSetup {
            name: "helix".into(),
            flight: FlightConfig::built(),
            imu: imu(),
            mocap: mocap(PoseMessage::Odometry),
            motor_time_constant_s: built_tau(),
            plant_mass_factor: 1.0,
            initial: at_rest(
                Vector3::new(3.0, 2.0, 6.0),
                UnitQuaternion::from_euler_angles(0.0, 0.0, 100.0f64.to_radians()),
            ),
            hold_s: 1.5,
            duration_s: 60.0,
            commands: vec![(0.0, arm(false)), (0.0, mission_start())],
            pose_outage: None,
            seed,
            ground_z: None,
        }
    }

    fn old_pose_loss(seed: u64) -> SilSetup {
        SilSetup {
            name: "pose-loss".into(),
            flight: FlightConfig::built(),
            imu: imu(),
            mocap: mocap(PoseMessage::AttPosMocap),
            motor_time_constant_s: built_tau(),
            plant_mass_factor: 1.0,
            initial: at_rest(Vector3::new(0.0, 0.0, 2.0), UnitQuaternion::identity()),
            hold_s: 1.5,
            duration_s: 10.0,
            commands: vec![(0.0, arm(false)), (0.0, takeoff(0.5))],
            pose_outage: Some((6.0, f64::INFINITY)),
            seed,
            ground_z: Some(0.0),
        }
    }

    fn old_takeoff_land(seed: u64) -> SilSetup {
        SilSetup {
            name: "takeoff-land".into(),
            flight: FlightConfig::built(),
            imu: imu(),
            mocap: mocap(PoseMessage::AttPosMocap),
            motor_time_constant_s: built_tau(),
            plant_mass_factor: 1.0,
            initial: at_rest(
                Vector3::zeros(),
                UnitQuaternion::from_euler_angles(0.0, 0.0, 0.5),
            ),
            hold_s: 1.5,
            duration_s: 50.0,
            commands: vec![
                (0.0, arm(false)),
                (0.2, takeoff(1.0)),
                (15.0, setpoint_nwu(Vector3::new(1.0, 0.5, 1.2), 1.0)),
                (30.0, land()),
            ],
            pose_outage: None,
            seed,
            ground_z: Some(0.0),
        }
    }

    #[test]
    fn files_build_the_old_setups_bit_for_bit() {
        for seed in [1, 7] {
            let pairs = [
                (paper(seed), old_paper(seed)),
                (pose_loss(seed), old_pose_loss(seed)),
                (takeoff_land(seed), old_takeoff_land(seed)),
                (helix(seed), old_helix(seed)),
            ];
            for (new, old) in pairs {
                assert_eq!(format!("{new:?}"), format!("{old:?}"), "{}", old.name);
            }
        }
        for name in NAMES {
            assert!(load(name, 1).is_ok(), "{name}");
        }
    }

    #[test]
    fn ground_station_builders_send_the_old_messages() {
        use firmware::ground_station as gs;
        let pairs = [
            (gs::arm(false), arm(false)),
            (gs::arm(true), arm(true)),
            (gs::takeoff(0.5), takeoff(0.5)),
            (gs::land(), land()),
            (gs::mission_start(), mission_start()),
            (gs::kill(), kill()),
            (
                gs::setpoint_nwu(Vector3::new(1.0, 0.5, 1.2), 1.0),
                setpoint_nwu(Vector3::new(1.0, 0.5, 1.2), 1.0),
            ),
        ];
        for (new, old) in pairs {
            assert_eq!(format!("{new:?}"), format!("{old:?}"));
        }
    }

    /// A file on disk: its name is its stem, and `initial.scenario` resolves next to it.
    #[test]
    fn loads_a_file_by_path() {
        let dir = std::env::temp_dir().join(format!("sil-scenario-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(
            dir.join("start.toml"),
            crate::model::scenario::PAPER_SCENARIO,
        )
        .unwrap();
        // The paper scenario with its start read from a scenario file next to it.
        let text: String = FILES[0]
            .lines()
            .filter(|l| !l.starts_with("euler_rad"))
            .map(|l| {
                if l.starts_with("position_m") {
                    "scenario = \"start.toml\"\n".to_string()
                } else {
                    format!("{l}\n")
                }
            })
            .collect();
        let path = dir.join("my-run.toml");
        std::fs::write(&path, text).unwrap();
        let s = load(path.to_str().unwrap(), 3).unwrap();
        assert_eq!(s.name, "my-run");
        let mut old = old_paper(3);
        old.name = "my-run".into();
        old.initial = Scenario::paper().initial_state();
        assert_eq!(format!("{s:?}"), format!("{old:?}"));
        let e = load(dir.join("missing.toml").to_str().unwrap(), 3).unwrap_err();
        assert!(format!("{e:#}").contains("unknown SIL scenario"), "{e:#}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
