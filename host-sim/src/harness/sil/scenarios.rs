//! The software-in-the-loop scenarios, and the ground-station messages they send.

use firmware::config::FlightConfig;
use firmware::frames;
use firmware::link::mavlink::dialects::common::{
    MavCmd, MavFrame, MavMessage, PositionTargetTypemask, COMMAND_LONG_DATA,
    SET_POSITION_TARGET_LOCAL_NED_DATA,
};
use nalgebra::{UnitQuaternion, Vector3};

use super::sensors::{ImuModel, MocapModel, PoseMessage};
use super::SilSetup;
use crate::plant::RigidBodyState;
use crate::scenario::Scenario;

/// The scenario names the CLI accepts.
pub const NAMES: [&str; 3] = ["paper", "pose-loss", "takeoff-land"];

/// `COMMAND_LONG` to system 1.
pub fn command(command: MavCmd, p1: f32, p2: f32, p7: f32) -> MavMessage {
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

/// Arm; `inverted` sets the explicit upside-down flag (param2 = 2989).
pub fn arm(inverted: bool) -> MavMessage {
    command(
        MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
        1.0,
        if inverted { 2989.0 } else { 0.0 },
        0.0,
    )
}

/// Takeoff to `height` \[m\] above the arming point.
pub fn takeoff(height: f32) -> MavMessage {
    command(MavCmd::MAV_CMD_NAV_TAKEOFF, 0.0, 0.0, height)
}

/// Land.
pub fn land() -> MavMessage {
    command(MavCmd::MAV_CMD_NAV_LAND, 0.0, 0.0, 0.0)
}

/// Start the helix demo.
pub fn mission_start() -> MavMessage {
    command(MavCmd::MAV_CMD_MISSION_START, 0.0, 0.0, 0.0)
}

/// Kill.
pub fn kill() -> MavMessage {
    command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 0.0, 21196.0, 0.0)
}

/// Hover target given in the controller's NWU frame \[m\] and yaw \[rad\], sent as MAVLink NED.
pub fn setpoint_nwu(position: Vector3<f32>, yaw: f32) -> MavMessage {
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

/// ICM-42688-P-class IMU at 1 kHz: gyro noise 3 mrad/s and bias (10, −20, 15) mrad/s,
/// accelerometer noise 0.05 m/s² and bias (0.05, −0.03, 0.08) m/s².
pub fn imu() -> ImuModel {
    ImuModel {
        rate_hz: 1000.0,
        gyro_noise: 3e-3,
        gyro_bias: [0.01, -0.02, 0.015],
        accel_noise: 0.05,
        accel_bias: [0.05, -0.03, 0.08],
    }
}

/// Motion capture at 100 Hz, 10 ms latency (as configured in the firmware), 2 % dropouts,
/// 0.5 mm and 2 mrad noise.
pub fn mocap(message: PoseMessage) -> MocapModel {
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

/// Scenario 1: the paper's Section VI flight from its upside-down start (roll −179°, 9.2 m
/// from the helix), held still 1.5 s for calibration, then released while the ground station
/// sends an explicit upside-down arm and the helix mission; 30 s with realistic sensors.
pub fn paper(seed: u64) -> SilSetup {
    SilSetup {
        name: "paper".into(),
        flight: FlightConfig::paper(),
        imu: imu(),
        mocap: mocap(PoseMessage::Odometry),
        motor_time_constant_s: 0.02,
        initial: Scenario::paper().initial_state(),
        hold_s: 1.5,
        duration_s: 30.0,
        commands: vec![(0.0, arm(true)), (0.0, mission_start())],
        pose_outage: None,
        seed,
        ground_z: None,
    }
}

/// Scenario 2: hand launch level at 2 m, take off to 2.5 m, hover; the pose stops at 6 s.
pub fn pose_loss(seed: u64) -> SilSetup {
    SilSetup {
        name: "pose-loss".into(),
        flight: FlightConfig::paper(),
        imu: imu(),
        mocap: mocap(PoseMessage::AttPosMocap),
        motor_time_constant_s: 0.02,
        initial: at_rest(Vector3::new(0.0, 0.0, 2.0), UnitQuaternion::identity()),
        hold_s: 1.5,
        duration_s: 10.0,
        commands: vec![(0.0, arm(false)), (0.0, takeoff(0.5))],
        pose_outage: Some((6.0, f64::INFINITY)),
        seed,
        ground_z: Some(0.0),
    }
}

/// Takeoff from the ground to 1 m, a hover target, landing and the automatic disarm.
pub fn takeoff_land(seed: u64) -> SilSetup {
    SilSetup {
        name: "takeoff-land".into(),
        flight: FlightConfig::paper(),
        imu: imu(),
        mocap: mocap(PoseMessage::AttPosMocap),
        motor_time_constant_s: 0.02,
        initial: at_rest(
            Vector3::zeros(),
            UnitQuaternion::from_euler_angles(0.0, 0.0, 0.5),
        ),
        hold_s: 1.5,
        duration_s: 20.0,
        commands: vec![
            (0.0, arm(false)),
            (0.2, takeoff(1.0)),
            (5.0, setpoint_nwu(Vector3::new(1.0, 0.5, 1.2), 1.0)),
            (10.0, land()),
        ],
        pose_outage: None,
        seed,
        ground_z: Some(0.0),
    }
}

/// The scenario called `name` (see [`NAMES`]).
pub fn by_name(name: &str, seed: u64) -> Option<SilSetup> {
    match name {
        "paper" => Some(paper(seed)),
        "pose-loss" => Some(pose_loss(seed)),
        "takeoff-land" => Some(takeoff_land(seed)),
        _ => None,
    }
}
