//! MAVLink 2 over a byte stream: a decoder that takes bytes in chunks of any size and never
//! panics ([`Decoder`]), the conversion of the accepted messages to the controller's frames
//! (through [`crate::frames`], the only place that converts; `interpret`), message signing
//! ([`signing`]) and the encoder for telemetry ([`encode`], [`encode_data`]).
//!
//! In: `ODOMETRY` (frame `MAV_FRAME_LOCAL_NED` or `MAV_FRAME_LOCAL_FRD`), `ATT_POS_MOCAP` and
//! `VISION_POSITION_ESTIMATE` (pose), `COMMAND_LONG` and `COMMAND_INT`
//! (`MAV_CMD_COMPONENT_ARM_DISARM` arm/disarm, with param2 = [`FORCE_DISARM_PARAM2`] (21196) a
//! kill, with param1 = 1 and param2 = [`FORCE_ARM_PARAM2`] (2989) an explicit upside-down arm;
//! `MAV_CMD_DO_FLIGHTTERMINATION` kill; `MAV_CMD_NAV_TAKEOFF` with param7 the height above the
//! arming point \[m\] (NaN/0: default); `MAV_CMD_NAV_LAND`; `MAV_CMD_MISSION_START` the uploaded
//! mission, or the helix demo without one; `MAV_CMD_REQUEST_MESSAGE` and `MAV_CMD_SET_MESSAGE_INTERVAL` for the messages it
//! sends; `MAV_CMD_DO_SET_MODE` with a custom mode; `MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES`;
//! any other command addressed to the vehicle is answered `MAV_RESULT_UNSUPPORTED`),
//! `SET_POSITION_TARGET_LOCAL_NED` (frame `MAV_FRAME_LOCAL_NED`, position and yaw; hover
//! target), `SETUP_SIGNING` (who may send it: [`LinkTrust`], [`SetupAuthority`]), `TIMESYNC`,
//! the mission protocol (`MISSION_*`, [`crate::mission`]) and the parameter protocol (`PARAM_REQUEST_LIST`,
//! `PARAM_REQUEST_READ`, `PARAM_SET`; [`crate::params`]). Out: `HEARTBEAT`,
//! `ATTITUDE_QUATERNION`, `LOCAL_POSITION_NED`, `SYS_STATUS`, `EXTENDED_SYS_STATE`, `ATTITUDE`,
//! `HOME_POSITION` and `AUTOPILOT_VERSION` (on request), `TIMESYNC`, `COMMAND_ACK` (to the
//! sender), `STATUSTEXT`, `PARAM_VALUE`, and the mission replies (`MISSION_COUNT`,
//! `MISSION_REQUEST_INT`, `MISSION_ITEM_INT`, `MISSION_ACK`, `MISSION_CURRENT`,
//! `MISSION_ITEM_REACHED`).
//!
//! Addressing: a message with a target (commands, setpoints, `SETUP_SIGNING`, parameter
//! messages) is used only if its target system is the vehicle's or 0 (broadcast) and its target
//! component the vehicle's or 0; any other is dropped and counted.
//!
//! With the `hil` feature only (the processor-in-the-loop build, never the flight build), also
//! in: `HIL_SENSOR` (the IMU over the link, body FRD); the pipeline then sends
//! `HIL_ACTUATOR_CONTROLS` and `POSITION_TARGET_LOCAL_NED` every tick.
//!
//! The frame parser is written here (not mavlink's reader) so that it works on a push of
//! bytes with no I/O trait, counts every failure, and resynchronises on the byte after a bad
//! start marker. The payloads are decoded by the `mavlink` crate.

pub use mavlink;

use mavlink::dialects::common::MavCmd;
use nalgebra::{Quaternion, Vector3};

mod ack;
pub mod crc;
mod decoder;
mod encode;
mod interpret;
mod interpret_mission;
pub mod mission_item;
mod mission_message;
pub mod signing;
#[cfg(test)]
mod tests;

pub use ack::CommandAck;
pub use decoder::Decoder;
pub use encode::{encode, encode_data};
pub use interpret::{FORCE_ARM_PARAM2, FORCE_DISARM_PARAM2};
pub use mission_item::MissionItem;
pub use mission_message::MissionMessage;
pub use signing::{SigningConfig, SIGNATURE};

/// MAVLink 2 start marker.
const STX: u8 = 0xFD;
/// Header bytes after the marker.
const HEADER: usize = 9;
/// Largest frame: marker + header + 255 payload + CRC + signature.
pub const MAX_FRAME: usize = 1 + HEADER + 255 + 2 + SIGNATURE;
/// `MAV_COMP_ID_AUTOPILOT1`: the component id a flight controller answers as.
pub const AUTOPILOT_COMPONENT: u8 = 1;

/// Where a pose came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PoseSource {
    /// `ODOMETRY`.
    Odometry,
    /// `ATT_POS_MOCAP`.
    Mocap,
    /// `VISION_POSITION_ESTIMATE` (what MAVROS' `vision_pose` plugin sends).
    Vision,
}

/// Whether a link's medium lets only the vehicle's owner put bytes on it, fixed when the
/// firmware is built (for the built flight: env `FIRMWARE_MAVLINK_LINK_TRUST`,
/// [`crate::built_flight::LINK_TRUST`]). It decides one thing: who may install or change the
/// signing key with `SETUP_SIGNING` (docs/mavlink.md, "Signing"). Every other message follows
/// the signing rules alike on both kinds of link.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LinkTrust {
    /// A wired console (a USB or UART cable to the owner's computer): whoever can send on it
    /// holds the vehicle. `SETUP_SIGNING` is taken unsigned, key or no key, so a lost key is
    /// replaced over the cable.
    Trusted,
    /// A radio, or any link a stranger in range may transmit on (the default): `SETUP_SIGNING`
    /// is taken only when signed with the key in force (the owner re-keying); without a key,
    /// never, so a stranger who is on the air first cannot install a key and lock the owner
    /// out.
    #[default]
    Untrusted,
}

impl LinkTrust {
    /// Name for logs: `trusted` or `untrusted`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Trusted => "trusted",
            Self::Untrusted => "untrusted",
        }
    }
}

/// What entitles a `SETUP_SIGNING` to change the signing key, as the decoder that received
/// it saw its frame ([`Inbound::SetupSigning`]). The pipeline installs the key only with
/// [`SetupAuthority::TrustedLink`] or [`SetupAuthority::SignedWithCurrentKey`], and only while
/// disarmed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SetupAuthority {
    /// It came over a link trusted at build time ([`LinkTrust::Trusted`]), signed or not.
    TrustedLink,
    /// It came over an untrusted link signed with the key in force, its signature checked and
    /// its timestamp newer than its stream's last (not a replay): the owner re-keying.
    SignedWithCurrentKey,
    /// Neither: unsigned, over an untrusted link that has no key yet. Refused: anyone in
    /// radio range could have sent it.
    Unauthenticated,
}

/// Who sent a message: its MAVLink header's system and component ids. Replies (`COMMAND_ACK`)
/// are addressed to it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Sender {
    /// Sender's system id.
    pub system: u8,
    /// Sender's component id.
    pub component: u8,
}

/// A command, already interpreted.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Command {
    /// Arm; `inverted` when the sender explicitly allows arming upside down.
    Arm {
        /// Explicit upside-down permission (param2 = [`FORCE_ARM_PARAM2`]).
        inverted: bool,
    },
    /// Disarm (only on the ground).
    Disarm,
    /// Stop the motors now, wherever the vehicle is.
    Kill,
    /// Take off to `height` \[m\] above the arming point (`None`: the configured default).
    Takeoff {
        /// Height \[m\], z up.
        height: Option<f32>,
    },
    /// Land below the current position.
    Land,
    /// Start the helix demo mission.
    StartHelix,
    /// Send message `id` once, now (`MAV_CMD_REQUEST_MESSAGE`, param1).
    RequestMessage {
        /// MAVLink message id.
        id: u32,
    },
    /// Fly in the reference mode `custom_mode` (`MAV_CMD_DO_SET_MODE` with
    /// `MAV_MODE_FLAG_CUSTOM_MODE_ENABLED` in param1 and the mode in param2: 1 hover where it
    /// is, 2 take off, 3 land, 4 the helix; as `HEARTBEAT.custom_mode`).
    SetMode {
        /// The custom mode, 1 to 4.
        custom_mode: u8,
    },
    /// Send message `id` every `interval_us` \[µs\] (`MAV_CMD_SET_MESSAGE_INTERVAL`: param1
    /// the id, param2 the interval; -1 stops it, 0 restores the default).
    SetMessageInterval {
        /// MAVLink message id.
        id: u32,
        /// Interval \[µs\] as sent (-1: stop, 0: default, > 0: the period).
        interval_us: f32,
    },
    /// `MAV_CMD_PREFLIGHT_STORAGE` with param1 = 2: back to the build's flight file (the
    /// set-up the pipeline was built with), stored parameters forgotten. Only while disarmed.
    ResetParams,
}

impl Command {
    /// Name for logs.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Arm { .. } => "arm",
            Self::Disarm => "disarm",
            Self::Kill => "kill",
            Self::Takeoff { .. } => "takeoff",
            Self::Land => "land",
            Self::StartHelix => "mission_start",
            Self::RequestMessage { .. } => "request_message",
            Self::SetMessageInterval { .. } => "set_message_interval",
            Self::SetMode { .. } => "set_mode",
            Self::ResetParams => "reset_params",
        }
    }
}

/// Why a command addressed to the vehicle cannot be run as sent: it is answered with a
/// `COMMAND_ACK` saying so and nothing else happens.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CommandFault {
    /// Not a command this vehicle runs (`MAV_RESULT_UNSUPPORTED`).
    Unsupported,
    /// A command it runs, with parameters it does not accept, e.g. an arm with param1 = 2
    /// (`MAV_RESULT_DENIED`).
    BadParameter,
}

/// An accepted message in the controller's frames (NWU inertial, FLU body, SI units).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Inbound {
    /// External pose: position \[m\] NWU and attitude FLU→NWU (not yet normalised; values may be
    /// non-finite, which the estimator refuses and counts).
    Pose {
        /// Position \[m\], NWU.
        position: Vector3<f32>,
        /// Attitude quaternion, FLU body to NWU, as received (not normalised).
        attitude: Quaternion<f32>,
        /// Message type.
        source: PoseSource,
    },
    /// A command with the MAVLink command id to acknowledge and who to acknowledge it to.
    Command {
        /// The interpreted command.
        command: Command,
        /// The MAVLink command to acknowledge.
        mav_cmd: MavCmd,
        /// Who sent it.
        sender: Sender,
    },
    /// A command addressed to the vehicle that it does not run as sent.
    CommandFault {
        /// The MAVLink command to acknowledge.
        mav_cmd: MavCmd,
        /// Why it is not run.
        fault: CommandFault,
        /// Who sent it.
        sender: Sender,
    },
    /// Hover target: position \[m\] NWU and yaw \[rad\] NWU (`None`: keep the current target yaw).
    Setpoint {
        /// Position \[m\], NWU.
        position: Vector3<f32>,
        /// Yaw \[rad\], NWU, if given.
        yaw: Option<f32>,
    },
    /// `SETUP_SIGNING`: a signing key to install or to replace the one in force with. The
    /// pipeline takes it only with `authority` [`SetupAuthority::TrustedLink`] or
    /// [`SetupAuthority::SignedWithCurrentKey`], and only while disarmed.
    SetupSigning {
        /// The 32-byte secret key.
        key: [u8; 32],
        /// Initial signing timestamp \[10 µs since 2015-01-01\].
        initial_timestamp: u64,
        /// What the link and the frame's signature entitle it to (set by the decoder).
        authority: SetupAuthority,
        /// Who sent it.
        sender: Sender,
    },
    /// `TIMESYNC` (no target: every system answers): a request when `tc1` is 0.
    Timesync {
        /// The responder's time \[ns\] (0 in a request).
        tc1: i64,
        /// The requester's time \[ns\], echoed in the answer.
        ts1: i64,
    },
    /// A message of the mission microservice (`MISSION_*`, [`crate::mission`]).
    Mission {
        /// The message.
        message: MissionMessage,
        /// Who sent it (replies are addressed to it).
        sender: Sender,
    },
    /// `PARAM_REQUEST_LIST`: send every parameter (`PARAM_VALUE`).
    ParamRequestList,
    /// `PARAM_REQUEST_READ`: send one parameter, by `index` when it is `>= 0`, else by name.
    ParamRequestRead {
        /// `param_id` as sent: NUL-padded ASCII, or 16 bytes with no NUL (unchecked).
        id: [u8; 16],
        /// `param_index` as sent (`-1`: use `id`).
        index: i16,
    },
    /// `PARAM_SET`: set a parameter (answered with `PARAM_VALUE`).
    ParamSet {
        /// `param_id` as sent: NUL-padded ASCII, or 16 bytes with no NUL (unchecked).
        id: [u8; 16],
        /// `param_value` as sent (may be non-finite: the pipeline refuses it).
        value: f32,
        /// Whether `param_type` is `MAV_PARAM_TYPE_REAL32`, the only type of this vehicle's
        /// parameters.
        real32: bool,
    },
    /// Simulated IMU sample (`HIL_SENSOR`, `hil` feature only), converted to body FLU.
    #[cfg(feature = "hil")]
    HilSensor {
        /// Angular rate \[rad/s\], body FLU (may be non-finite: the estimator refuses it).
        gyro_rad_s: [f32; 3],
        /// Specific force \[m/s²\], body FLU.
        accel_m_s2: [f32; 3],
        /// Sample time \[µs\] on the simulation's clock (`time_usec`).
        time_us: u64,
    },
}

/// `HIL_SENSOR.fields_updated` bits 0–5: accelerometer x, y, z and gyro x, y, z (MAVLink
/// `HIL_SENSOR_UPDATED_FLAGS`). A sample without all six is not an IMU sample.
#[cfg(feature = "hil")]
pub const HIL_SENSOR_IMU_FIELDS: u32 = 0b11_1111;

/// Link counters (monotone, wrapping never in practice: u32 at 300 frames/s lasts 165 days).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LinkCounters {
    /// Frames with a valid CRC (and signature, where one is required) that were used.
    pub frames_ok: u32,
    /// Valid frames not used: unknown message id, another target, a frame or command not
    /// supported.
    pub frames_dropped: u32,
    /// Frames refused: bad CRC, unknown incompatibility flags, undecodable payload.
    pub frames_malformed: u32,
    /// Bytes skipped while looking for a start marker.
    pub bytes_discarded: u32,
    /// Signed frames dropped because the vehicle has no key (the MAVLink 2 signing rule for a
    /// system that does not verify signatures).
    pub signed_without_key: u32,
    /// Signed frames whose signature does not match the vehicle's key.
    pub bad_signature: u32,
    /// Signed frames with a timestamp not after the last one of their stream (a replay), or a
    /// new stream more than a minute behind the vehicle's signing clock.
    pub stale_signature: u32,
    /// Unsigned frames refused while signing is active (commands, setpoints, parameter sets,
    /// and `SETUP_SIGNING` on an untrusted link; poses and sensor samples too unless
    /// [`SigningConfig::accept_unsigned_sensors`]).
    pub unsigned_refused: u32,
}
