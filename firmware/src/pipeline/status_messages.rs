//! The status messages a ground station (QGroundControl, MAVProxy) and MAVROS need to show and
//! drive the vehicle: `SYS_STATUS`, `EXTENDED_SYS_STATE`, `ATTITUDE`, `HOME_POSITION`,
//! `AUTOPILOT_VERSION`, and the `TIMESYNC` answer. Built from the pipeline's state; frames
//! NED/FRD as MAVLink wants them ([`crate::frames`]).

use mavlink::dialects::common::{
    MavLandedState, MavProtocolCapability, MavSysStatusSensor, MavVtolState, ATTITUDE_DATA,
    AUTOPILOT_VERSION_DATA, EXTENDED_SYS_STATE_DATA, HOME_POSITION_DATA, SYS_STATUS_DATA,
};
use nalgebra::{Quaternion, UnitQuaternion, Vector3};

use super::{FlightPipeline, Mode};
use crate::frames;
use crate::safety::FlightState;

/// What the vehicle really does (`AUTOPILOT_VERSION.capabilities`): parameters (REAL32 values,
/// for which C-cast and bytewise encodings agree),
/// `COMMAND_INT`, missions as `MISSION_ITEM_INT`, local position targets, flight termination, MAVLink 2.
pub const CAPABILITIES: MavProtocolCapability =
    MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_COMMAND_INT
        .union(MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_MISSION_INT)
        .union(MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_SET_POSITION_TARGET_LOCAL_NED)
        .union(MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_FLIGHT_TERMINATION)
        .union(MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_MAVLINK2)
        .union(MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_PARAM_ENCODE_C_CAST);

/// `flight_sw_version`: major, minor, patch of the crate, and `FIRMWARE_VERSION_TYPE_DEV` (0)
/// in the low byte (MAVLink's packing).
fn flight_sw_version() -> u32 {
    let part = |s: &str| s.parse::<u32>().unwrap_or(0) & 0xFF;
    part(env!("CARGO_PKG_VERSION_MAJOR")) << 24
        | part(env!("CARGO_PKG_VERSION_MINOR")) << 16
        | part(env!("CARGO_PKG_VERSION_PATCH")) << 8
}

impl FlightPipeline {
    /// `SYS_STATUS`: gyro, accelerometer, external pose (`VISION_POSITION`), the control loops
    /// and the motor outputs; enabled: the sensors always, the loops and motors when armed;
    /// healthy: IMU once calibrated, pose while fresh (younger than the failsafe age), loops
    /// and motors unless in failsafe. `load`: the control step's share of its period
    /// \[per mille\] as the control loop last reported it ([`FlightPipeline::report_load`]; 0 in
    /// the processor-in-the-loop build, whose step durations depend on the host).
    /// No battery is measured (voltage `u16::MAX`, current and remaining −1: unknown).
    pub(super) fn sys_status(&self) -> SYS_STATUS_DATA {
        use MavSysStatusSensor as S;
        let sensors = S::MAV_SYS_STATUS_SENSOR_3D_GYRO
            | S::MAV_SYS_STATUS_SENSOR_3D_ACCEL
            | S::MAV_SYS_STATUS_SENSOR_VISION_POSITION;
        let control = S::MAV_SYS_STATUS_SENSOR_ANGULAR_RATE_CONTROL
            | S::MAV_SYS_STATUS_SENSOR_ATTITUDE_STABILIZATION
            | S::MAV_SYS_STATUS_SENSOR_YAW_POSITION
            | S::MAV_SYS_STATUS_SENSOR_Z_ALTITUDE_CONTROL
            | S::MAV_SYS_STATUS_SENSOR_XY_POSITION_CONTROL
            | S::MAV_SYS_STATUS_SENSOR_MOTOR_OUTPUTS;
        let state = self.supervisor.state();
        let mut enabled = sensors;
        if state != FlightState::Disarmed {
            enabled |= control;
        }
        let mut health = S::empty();
        if !self.estimator.calibrating() {
            health |= S::MAV_SYS_STATUS_SENSOR_3D_GYRO | S::MAV_SYS_STATUS_SENSOR_3D_ACCEL;
        }
        if self.status_pose_age <= self.cfg.safety.failsafe_pose_age_us {
            health |= S::MAV_SYS_STATUS_SENSOR_VISION_POSITION;
        }
        if state != FlightState::Failsafe {
            health |= control;
        }
        SYS_STATUS_DATA {
            onboard_control_sensors_present: sensors | control,
            onboard_control_sensors_enabled: enabled,
            onboard_control_sensors_health: health,
            load: self.load_permille,
            voltage_battery: u16::MAX,
            current_battery: -1,
            drop_rate_comm: 0,
            errors_comm: self.counters.link.frames_malformed.min(u32::from(u16::MAX)) as u16,
            errors_count1: 0,
            errors_count2: 0,
            errors_count3: 0,
            errors_count4: 0,
            battery_remaining: -1,
        }
    }

    /// `EXTENDED_SYS_STATE`: landed state from the supervisor and the reference mode
    /// (disarmed or armed at idle: on the ground; takeoff; landing; otherwise in the air).
    pub(super) fn extended_sys_state(&self) -> EXTENDED_SYS_STATE_DATA {
        let landed_state = match (self.supervisor.state(), self.mission.mode()) {
            (FlightState::Disarmed, _) | (_, Mode::Idle) => {
                MavLandedState::MAV_LANDED_STATE_ON_GROUND
            }
            (_, Mode::Takeoff) => MavLandedState::MAV_LANDED_STATE_TAKEOFF,
            (_, Mode::Land) => MavLandedState::MAV_LANDED_STATE_LANDING,
            _ => MavLandedState::MAV_LANDED_STATE_IN_AIR,
        };
        EXTENDED_SYS_STATE_DATA {
            vtol_state: MavVtolState::MAV_VTOL_STATE_UNDEFINED,
            landed_state,
        }
    }

    /// `ATTITUDE`: roll, pitch, yaw \[rad\] (Z-Y-X, FRD body to NED) and body rates \[rad/s\]
    /// (FRD) of the estimate.
    pub(super) fn attitude_euler(&self, now_us: u64) -> ATTITUDE_DATA {
        let [w, x, y, z] = frames::quaternion_to_mavlink(&self.status_attitude);
        let (roll, pitch, yaw) =
            UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z)).euler_angles();
        let rates = frames::flip_to_array(&Vector3::from(self.status_rates));
        ATTITUDE_DATA {
            time_boot_ms: (now_us / 1000) as u32,
            roll,
            pitch,
            yaw,
            rollspeed: rates[0],
            pitchspeed: rates[1],
            yawspeed: rates[2],
        }
    }

    /// `HOME_POSITION`: the last arming point in the local frame (x, y, z NED \[m\]); no
    /// global position is known (latitude, longitude, altitude 0), `q` identity, no approach.
    pub(super) fn home_position(&self) -> HOME_POSITION_DATA {
        let p = frames::flip_to_array(&self.home);
        HOME_POSITION_DATA {
            latitude: 0,
            longitude: 0,
            altitude: 0,
            x: p[0],
            y: p[1],
            z: p[2],
            q: [1.0, 0.0, 0.0, 0.0],
            approach_x: 0.0,
            approach_y: 0.0,
            approach_z: 0.0,
        }
    }

    /// `AUTOPILOT_VERSION`: [`CAPABILITIES`], this crate's version; no vendor, product or
    /// unique id.
    pub(super) fn autopilot_version(&self) -> AUTOPILOT_VERSION_DATA {
        AUTOPILOT_VERSION_DATA {
            capabilities: CAPABILITIES,
            flight_sw_version: flight_sw_version(),
            ..Default::default()
        }
    }

    /// The control step's share of its period \[per mille\], for `SYS_STATUS.load`: the
    /// control loop reports it once per timing window (e.g. mean step time / period).
    pub fn report_load(&mut self, permille: u16) {
        self.load_permille = permille.min(1000);
    }
}
