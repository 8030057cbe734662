//! From a checked MAVLink payload to an [`Inbound`] message in the controller's frames: which
//! messages are used, addressing (target system and component), command parameters.
//! Parameter messages are passed on as sent (names and values are the pipeline's to check).

#[cfg(feature = "hil")]
use mavlink::dialects::common::HIL_SENSOR_DATA;
use mavlink::dialects::common::{
    MavCmd, MavFrame, MavParamType, ATT_POS_MOCAP_DATA, AUTOPILOT_VERSION_DATA, COMMAND_INT_DATA,
    COMMAND_LONG_DATA, ODOMETRY_DATA, PARAM_REQUEST_LIST_DATA, PARAM_REQUEST_READ_DATA,
    PARAM_SET_DATA, SETUP_SIGNING_DATA, SET_POSITION_TARGET_LOCAL_NED_DATA, TIMESYNC_DATA,
    VISION_POSITION_ESTIMATE_DATA,
};
use mavlink::{MavlinkVersion, MessageData};

use super::{Command, CommandFault, Inbound, PoseSource, Sender, SetupAuthority};
use crate::frames;

/// `COMMAND_LONG` param2 of `MAV_CMD_COMPONENT_ARM_DISARM` with param1 = 0 that disarms in
/// flight: a kill (PX4's magic number, MAVLink common's "force disarm").
pub const FORCE_DISARM_PARAM2: f32 = 21196.0;
/// `COMMAND_LONG` param2 of `MAV_CMD_COMPONENT_ARM_DISARM` with param1 = 1 that forces the arm
/// (PX4's magic number, MAVLink common's "force arm"); here the explicit permission to arm
/// upside down.
pub const FORCE_ARM_PARAM2: f32 = 2989.0;

/// What a checked frame turned out to be.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Interpretation {
    /// Used: the message is in the caller's `out`.
    Accepted,
    /// Valid but not for us or not used (counted as dropped).
    Ignored,
    /// Undecodable or impossible content (counted as malformed).
    Malformed,
}

/// Whom a decoder answers as.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Address {
    pub system: u8,
    pub component: u8,
}

impl Address {
    /// Target system and component each ours or 0 (broadcast).
    pub(super) fn accepts(&self, system: u8, component: u8) -> bool {
        (system == 0 || system == self.system) && (component == 0 || component == self.component)
    }
}

/// `m` into `out`: [`Interpretation::Accepted`].
#[inline(always)]
fn accept(out: &mut Option<Inbound>, m: Inbound) -> Interpretation {
    *out = Some(m);
    Interpretation::Accepted
}

/// Message ids whose frames carry commands or change what the vehicle does (`PARAM_SET`
/// changes gains and limits): with signing active they must be signed, whatever the settings.
/// Parameter reads are not: they change nothing.
pub(super) fn is_command(msgid: u32) -> bool {
    matches!(
        msgid,
        COMMAND_LONG_DATA::ID
            | COMMAND_INT_DATA::ID
            | SET_POSITION_TARGET_LOCAL_NED_DATA::ID
            | SETUP_SIGNING_DATA::ID
            | PARAM_SET_DATA::ID
    ) || super::interpret_mission::changes_mission(msgid)
}

/// Decodes and interprets the payload of message `msgid` from `sender`, for `us`.
///
/// The message goes straight into `out` (which the caller passes as `None`), not through the
/// return value: an [`Inbound`] is 48 bytes, and moving it from one enum to another (this
/// verdict, the decoder's, its `Option`) cost two `memcpy` calls per frame on the MCU, most of
/// the pose frame's decoding.
#[inline(always)]
pub(super) fn interpret(
    us: Address,
    sender: Sender,
    msgid: u32,
    payload: &[u8],
    out: &mut Option<Inbound>,
) -> Interpretation {
    let v = MavlinkVersion::V2;
    macro_rules! decode {
        ($t:ty) => {
            match <$t>::deser(v, payload) {
                Ok(m) => m,
                Err(_) => return Interpretation::Malformed,
            }
        };
    }
    match msgid {
        ODOMETRY_DATA::ID => odometry(&decode!(ODOMETRY_DATA), out),
        ATT_POS_MOCAP_DATA::ID => {
            let m = decode!(ATT_POS_MOCAP_DATA);
            accept(
                out,
                Inbound::Pose {
                    position: frames::flip_vector([m.x, m.y, m.z]),
                    attitude: frames::flip_quaternion(m.q),
                    source: PoseSource::Mocap,
                },
            )
        }
        VISION_POSITION_ESTIMATE_DATA::ID => {
            let m = decode!(VISION_POSITION_ESTIMATE_DATA);
            accept(
                out,
                Inbound::Pose {
                    position: frames::flip_vector([m.x, m.y, m.z]),
                    attitude: frames::flip_quaternion(frames::euler_to_quaternion(
                        m.roll, m.pitch, m.yaw,
                    )),
                    source: PoseSource::Vision,
                },
            )
        }
        COMMAND_LONG_DATA::ID => {
            let m = decode!(COMMAND_LONG_DATA);
            if !us.accepts(m.target_system, m.target_component) {
                return Interpretation::Ignored;
            }
            command(
                m.command,
                [m.param1, m.param2, m.param3, m.param4, m.param7],
                sender,
                out,
            )
        }
        COMMAND_INT_DATA::ID => {
            let m = decode!(COMMAND_INT_DATA);
            if !us.accepts(m.target_system, m.target_component) {
                return Interpretation::Ignored;
            }
            // COMMAND_INT's x and y are scaled integers (positions); none of the commands run
            // here uses them, and its z is COMMAND_LONG's param7.
            command(
                m.command,
                [m.param1, m.param2, m.param3, m.param4, m.z],
                sender,
                out,
            )
        }
        SET_POSITION_TARGET_LOCAL_NED_DATA::ID => {
            let m = decode!(SET_POSITION_TARGET_LOCAL_NED_DATA);
            if !us.accepts(m.target_system, m.target_component) {
                return Interpretation::Ignored;
            }
            setpoint(&m, out)
        }
        SETUP_SIGNING_DATA::ID => {
            let m = decode!(SETUP_SIGNING_DATA);
            if !us.accepts(m.target_system, m.target_component) {
                return Interpretation::Ignored;
            }
            accept(
                out,
                Inbound::SetupSigning {
                    key: m.secret_key,
                    initial_timestamp: m.initial_timestamp,
                    // The payload alone proves nothing: the decoder, which knows the link and
                    // the frame's signature, raises it where they entitle it.
                    authority: SetupAuthority::Unauthenticated,
                    sender,
                },
            )
        }
        TIMESYNC_DATA::ID => {
            let m = decode!(TIMESYNC_DATA);
            accept(
                out,
                Inbound::Timesync {
                    tc1: m.tc1,
                    ts1: m.ts1,
                },
            )
        }
        PARAM_REQUEST_LIST_DATA::ID => {
            let m = decode!(PARAM_REQUEST_LIST_DATA);
            if !us.accepts(m.target_system, m.target_component) {
                return Interpretation::Ignored;
            }
            accept(out, Inbound::ParamRequestList)
        }
        PARAM_REQUEST_READ_DATA::ID => {
            let m = decode!(PARAM_REQUEST_READ_DATA);
            if !us.accepts(m.target_system, m.target_component) {
                return Interpretation::Ignored;
            }
            accept(
                out,
                Inbound::ParamRequestRead {
                    id: m.param_id.into(),
                    index: m.param_index,
                },
            )
        }
        PARAM_SET_DATA::ID => {
            let m = decode!(PARAM_SET_DATA);
            if !us.accepts(m.target_system, m.target_component) {
                return Interpretation::Ignored;
            }
            accept(
                out,
                Inbound::ParamSet {
                    id: m.param_id.into(),
                    value: m.param_value,
                    real32: m.param_type == MavParamType::MAV_PARAM_TYPE_REAL32,
                },
            )
        }
        #[cfg(feature = "hil")]
        HIL_SENSOR_DATA::ID => hil_sensor(&decode!(HIL_SENSOR_DATA), out),
        _ => super::interpret_mission::interpret(us, sender, msgid, payload, out)
            .unwrap_or(Interpretation::Ignored),
    }
}

#[cfg(feature = "hil")]
fn hil_sensor(m: &HIL_SENSOR_DATA, out: &mut Option<Inbound>) -> Interpretation {
    if m.fields_updated.bits() & super::HIL_SENSOR_IMU_FIELDS != super::HIL_SENSOR_IMU_FIELDS {
        return Interpretation::Ignored;
    }
    // FRD → FLU is the same axis flip as NED → NWU.
    let gyro = frames::flip_vector([m.xgyro, m.ygyro, m.zgyro]);
    let accel = frames::flip_vector([m.xacc, m.yacc, m.zacc]);
    accept(
        out,
        Inbound::HilSensor {
            gyro_rad_s: [gyro.x, gyro.y, gyro.z],
            accel_m_s2: [accel.x, accel.y, accel.z],
            time_us: m.time_usec,
        },
    )
}

fn odometry(m: &ODOMETRY_DATA, out: &mut Option<Inbound>) -> Interpretation {
    if !matches!(
        m.frame_id,
        MavFrame::MAV_FRAME_LOCAL_NED | MavFrame::MAV_FRAME_LOCAL_FRD
    ) {
        return Interpretation::Ignored;
    }
    accept(
        out,
        Inbound::Pose {
            position: frames::flip_vector([m.x, m.y, m.z]),
            attitude: frames::flip_quaternion(m.q),
            source: PoseSource::Odometry,
        },
    )
}

/// A command from `COMMAND_LONG` or `COMMAND_INT`: `p` is param1–4 and param7 (`COMMAND_INT`'s
/// z). Every command gets an [`Inbound`] so that it is acknowledged: the ones run here as
/// [`Inbound::Command`], the others as [`Inbound::CommandFault`].
// MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES is deprecated for REQUEST_MESSAGE, but MAVProxy and
// older ground stations still send it.
#[allow(deprecated)]
fn command(
    mav_cmd: MavCmd,
    p: [f32; 5],
    sender: Sender,
    out: &mut Option<Inbound>,
) -> Interpretation {
    let [p1, p2, _p3, _p4, p7] = p;
    let mut fault = |fault| {
        accept(
            out,
            Inbound::CommandFault {
                mav_cmd,
                fault,
                sender,
            },
        )
    };
    let c = match mav_cmd {
        MavCmd::MAV_CMD_COMPONENT_ARM_DISARM => {
            if p1 == 1.0 {
                Command::Arm {
                    inverted: p2 == FORCE_ARM_PARAM2,
                }
            } else if p1 == 0.0 {
                if p2 == FORCE_DISARM_PARAM2 {
                    Command::Kill
                } else {
                    Command::Disarm
                }
            } else {
                return fault(CommandFault::BadParameter);
            }
        }
        MavCmd::MAV_CMD_DO_FLIGHTTERMINATION if p1 >= 0.5 => Command::Kill,
        MavCmd::MAV_CMD_DO_FLIGHTTERMINATION => return fault(CommandFault::BadParameter),
        MavCmd::MAV_CMD_NAV_TAKEOFF => Command::Takeoff {
            height: (p7.is_finite() && p7 > 0.0).then_some(p7),
        },
        MavCmd::MAV_CMD_NAV_LAND => Command::Land,
        MavCmd::MAV_CMD_MISSION_START => Command::StartHelix,
        MavCmd::MAV_CMD_REQUEST_MESSAGE => match message_id(p1) {
            Some(id) => Command::RequestMessage { id },
            None => return fault(CommandFault::BadParameter),
        },
        MavCmd::MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES if p1 == 1.0 => Command::RequestMessage {
            id: AUTOPILOT_VERSION_DATA::ID,
        },
        MavCmd::MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES => return fault(CommandFault::BadParameter),
        MavCmd::MAV_CMD_DO_SET_MODE => {
            // MAV_MODE_FLAG_CUSTOM_MODE_ENABLED (1) must be set; the custom modes are 1-4.
            let custom = message_id(p2).filter(|m| (1..=4).contains(m));
            match custom {
                Some(m) if (p1 as u32) & 1 == 1 && p1.is_finite() => Command::SetMode {
                    custom_mode: m as u8,
                },
                _ => return fault(CommandFault::BadParameter),
            }
        }
        MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL => match message_id(p1) {
            Some(id) if p2.is_finite() && p2 >= -1.0 => Command::SetMessageInterval {
                id,
                interval_us: p2,
            },
            _ => return fault(CommandFault::BadParameter),
        },
        // 2: reset the parameters to the build's. Reading (0) and writing (1) are not
        // commands here: every accepted PARAM_SET is saved, and stored values load at boot.
        MavCmd::MAV_CMD_PREFLIGHT_STORAGE if p1 == 2.0 => Command::ResetParams,
        _ => return fault(CommandFault::Unsupported),
    };
    accept(
        out,
        Inbound::Command {
            command: c,
            mav_cmd,
            sender,
        },
    )
}

/// A message id carried in a float parameter: a whole number in the 24-bit id range.
fn message_id(p: f32) -> Option<u32> {
    ((0.0..16_777_216.0).contains(&p) && libm::truncf(p) == p).then_some(p as u32)
}

fn setpoint(m: &SET_POSITION_TARGET_LOCAL_NED_DATA, out: &mut Option<Inbound>) -> Interpretation {
    use mavlink::dialects::common::PositionTargetTypemask as Mask;
    if m.coordinate_frame != MavFrame::MAV_FRAME_LOCAL_NED {
        return Interpretation::Ignored;
    }
    let ignore_pos = Mask::POSITION_TARGET_TYPEMASK_X_IGNORE
        | Mask::POSITION_TARGET_TYPEMASK_Y_IGNORE
        | Mask::POSITION_TARGET_TYPEMASK_Z_IGNORE;
    if m.type_mask.intersects(ignore_pos) {
        // Only full position targets are hover targets.
        return Interpretation::Ignored;
    }
    let position = frames::flip_vector([m.x, m.y, m.z]);
    if !position.iter().all(|x| x.is_finite()) {
        return Interpretation::Malformed;
    }
    let yaw = (!m
        .type_mask
        .contains(Mask::POSITION_TARGET_TYPEMASK_YAW_IGNORE)
        && m.yaw.is_finite())
    .then(|| frames::flip_yaw(m.yaw));
    accept(out, Inbound::Setpoint { position, yaw })
}
