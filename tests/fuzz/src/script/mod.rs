//! The pipeline target's input format: a byte string read as a script of operations on a
//! [`firmware::pipeline::FlightPipeline`], with an encoder so that recorded flights
//! ([`crate::capture`]) become seeds.
//!
//! Each operation starts with a tag byte (`tag % 6`); its fields follow, little-endian, and an
//! input that ends inside a field reads the missing bytes as 0 (every byte string is a valid
//! script). One clock \[µs\] runs through the script, starting at 0:
//!
//! | tag | operation | fields | clock |
//! |---|---|---|---|
//! | 0 | [`Op::Bytes`]: raw link bytes | `n: u8`, `n` bytes | — |
//! | 1 | [`Op::Frame`]: a CRC-valid MAVLink 2 frame built from fields | see [`FrameSpec`] (kind byte mod 6; kind 5 the mission protocol, [`MissionSpec`]) | — |
//! | 2 | [`Op::Imu`]: an IMU sample, any `f32` | gyro \[rad/s\] 3×`f32`, accel \[m/s²\] 3×`f32`, `dt: u16` \[µs\] | `+dt` |
//! | 3 | [`Op::ImuQuantised`]: an IMU sample 1 ms after the last | gyro 3×`i16` \[mrad/s\], accel 3×`i16` \[cm/s²\] | `+1000` |
//! | 4 | [`Op::Rest`]: `n` samples of a vehicle at rest, 1 ms apart | `n: u8` | `+1000 n` |
//! | 5 | [`Op::Tick`]: a control tick, then telemetry into a buffer of `room` bytes | `dt: u16` \[µs\], `room: u16` (mod 2048) | `+dt` |
//!
//! Frames are the only way a fuzzer gets past the CRC; raw bytes reach everything else in the
//! decoder (the [`crate::targets::link_decoder`] target covers it alone).

use firmware::link::mavlink::dialects::common::{MavCmd, MavMissionResult};

mod encode;
mod messages;
mod reader;
#[cfg(test)]
mod tests;

pub use encode::encode;
pub use messages::{frame_bytes, message, mission_frame};
pub use reader::parse;

/// Standard gravity \[m/s²\] of the at-rest samples ([`Op::Rest`]); the pipeline's vehicles use
/// 9.81.
pub const REST_ACCEL_M_S2: f32 = 9.81;

/// The commands a [`FrameSpec::Command`] chooses from (index mod the length): those the
/// firmware interprets, and one it does not.
pub const COMMANDS: [MavCmd; 6] = [
    MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
    MavCmd::MAV_CMD_DO_FLIGHTTERMINATION,
    MavCmd::MAV_CMD_NAV_TAKEOFF,
    MavCmd::MAV_CMD_NAV_LAND,
    MavCmd::MAV_CMD_MISSION_START,
    MavCmd::MAV_CMD_DO_SET_MODE,
];

/// The item commands a mission item ([`MissionSpec::ItemInt`], [`MissionSpec::Item`]) chooses
/// from (index mod the length): the three the firmware plans, and one it refuses.
pub const MISSION_COMMANDS: [MavCmd; 4] = [
    MavCmd::MAV_CMD_NAV_WAYPOINT,
    MavCmd::MAV_CMD_NAV_TAKEOFF,
    MavCmd::MAV_CMD_NAV_LAND,
    MavCmd::MAV_CMD_NAV_LOITER_UNLIM,
];

/// The `MISSION_ACK` results a [`MissionSpec::Ack`] chooses from (index mod the length).
pub const MISSION_RESULTS: [MavMissionResult; 4] = [
    MavMissionResult::MAV_MISSION_ACCEPTED,
    MavMissionResult::MAV_MISSION_ERROR,
    MavMissionResult::MAV_MISSION_DENIED,
    MavMissionResult::MAV_MISSION_OPERATION_CANCELLED,
];

/// The messages of a [`FrameSpec::Mission`] (sub-kind byte mod 9) and their fields after the
/// target system byte. `mission_type` is always 0 (the mission; the `mavlink` crate's structs
/// do not carry the extension field).
#[derive(Clone, Debug, PartialEq)]
pub enum MissionSpec {
    /// Sub-kind 0, `MISSION_COUNT`: `count: u16` (an upload of that many items).
    Count {
        /// Number of items.
        count: u16,
    },
    /// Sub-kind 1, `MISSION_ITEM_INT`: `seq: u16`, command index `u8` into
    /// [`MISSION_COMMANDS`], frame `u8` ([`mission_frame`]), `x`, `y` 2×`i32` (local: m × 10⁴),
    /// `z` `f32` \[m\], param1..param4 4×`f32`.
    ItemInt {
        /// Sequence number.
        seq: u16,
        /// Index into [`MISSION_COMMANDS`] (mod its length).
        command: u8,
        /// `frame` number ([`mission_frame`]).
        frame: u8,
        /// `x`, `y`: local frames north, east \[m × 10⁴\]; global ones latitude, longitude.
        xy: [i32; 2],
        /// `z` \[m\].
        z: f32,
        /// param1..param4.
        params: [f32; 4],
    },
    /// Sub-kind 2, `MISSION_ITEM` (the deprecated float item): as [`MissionSpec::ItemInt`] with
    /// `x`, `y` 2×`f32` (local: m).
    Item {
        /// Sequence number.
        seq: u16,
        /// Index into [`MISSION_COMMANDS`] (mod its length).
        command: u8,
        /// `frame` number ([`mission_frame`]).
        frame: u8,
        /// `x`, `y` \[m\] (global frames: degrees).
        xy: [f32; 2],
        /// `z` \[m\].
        z: f32,
        /// param1..param4.
        params: [f32; 4],
    },
    /// Sub-kind 3, `MISSION_REQUEST_INT`: `seq: u16` (a download's item).
    RequestInt {
        /// Sequence number.
        seq: u16,
    },
    /// Sub-kind 4, `MISSION_REQUEST_LIST`: no fields.
    RequestList,
    /// Sub-kind 5, `MISSION_CLEAR_ALL`: no fields.
    ClearAll,
    /// Sub-kind 6, `MISSION_SET_CURRENT` (deprecated, still sent): `seq: u16`.
    SetCurrent {
        /// Sequence number.
        seq: u16,
    },
    /// Sub-kind 7, `MISSION_ACK`: result index `u8` into [`MISSION_RESULTS`] (it ends or
    /// cancels an upload).
    Ack {
        /// Index into [`MISSION_RESULTS`] (mod its length).
        result: u8,
    },
    /// Sub-kind 8, `SET_GPS_GLOBAL_ORIGIN` (the origin global items are placed about):
    /// latitude, longitude `i32` \[deg × 10⁷\], altitude `i32` \[mm\].
    SetOrigin {
        /// Latitude, longitude \[deg × 10⁷\], altitude \[mm\].
        lla: [i32; 3],
    },
}

/// The frame kinds of [`Op::Frame`] (kind byte mod 6) and their fields after the kind byte.
#[derive(Clone, Debug, PartialEq)]
pub enum FrameSpec {
    /// Kind 0, `ATT_POS_MOCAP`: position \[m\] NED 3×`f32`, quaternion (w, x, y, z; FRD→NED)
    /// 4×`f32`.
    Mocap {
        /// Position \[m\], NED.
        position: [f32; 3],
        /// Attitude quaternion (w, x, y, z), FRD body to NED, not necessarily unit.
        q: [f32; 4],
    },
    /// Kind 1, `ODOMETRY`: frame id `u8` (as a `MavFrame` number), then as [`FrameSpec::Mocap`].
    Odometry {
        /// `frame_id` number (0, 1, 7, 12, 20, 21 as in MAVLink; any other reads as
        /// `MAV_FRAME_LOCAL_NED`).
        frame: u8,
        /// Position \[m\].
        position: [f32; 3],
        /// Attitude quaternion (w, x, y, z).
        q: [f32; 4],
    },
    /// Kind 2, `COMMAND_LONG`: command index `u8` into [`COMMANDS`], target system `u8`,
    /// param1, param2, param7 3×`f32`.
    Command {
        /// Index into [`COMMANDS`] (mod its length).
        command: u8,
        /// Target system (0: broadcast; the vehicle is 1).
        target: u8,
        /// param1, param2, param7.
        params: [f32; 3],
    },
    /// Kind 3, `SET_POSITION_TARGET_LOCAL_NED`: frame id `u8`, type mask `u16`, target system
    /// `u8`, position \[m\] NED 3×`f32`, yaw \[rad\] `f32`.
    Setpoint {
        /// `coordinate_frame` number.
        frame: u8,
        /// `type_mask` bits.
        mask: u16,
        /// Target system.
        target: u8,
        /// Position \[m\], NED.
        position: [f32; 3],
        /// Yaw \[rad\], NED.
        yaw: f32,
    },
    /// Kind 4, `HIL_SENSOR`: `fields_updated` `u32`, accel \[m/s²\] 3×`f32`, gyro \[rad/s\]
    /// 3×`f32` (body FRD), time offset `i32` \[µs\] from the script's clock.
    HilSensor {
        /// `fields_updated` bits (the IMU needs bits 0-5).
        fields: u32,
        /// Specific force \[m/s²\], FRD.
        accel: [f32; 3],
        /// Angular rate \[rad/s\], FRD.
        gyro: [f32; 3],
        /// `time_usec` minus the clock \[µs\].
        time_offset_us: i32,
    },
    /// Kind 5, the mission protocol (`MISSION_*`): sub-kind `u8` (mod 9, see [`MissionSpec`]),
    /// target system `u8`, then the sub-kind's fields.
    Mission {
        /// Target system (0: broadcast; the vehicle is 1).
        target: u8,
        /// The message and its fields.
        message: MissionSpec,
    },
}

/// One operation of a script (see the module's table).
#[derive(Clone, Debug, PartialEq)]
pub enum Op {
    /// Raw bytes into `on_link_bytes` (at most 255).
    Bytes(Vec<u8>),
    /// A CRC-valid frame into `on_link_bytes` in chunks of `chunk` bytes (`chunk` byte mod 64,
    /// plus 1; it follows the frame's fields).
    Frame {
        /// The frame's content.
        spec: FrameSpec,
        /// Chunk length of the delivery, 1..=64.
        chunk: u8,
    },
    /// An IMU sample `dt` \[µs\] after the last operation's time.
    Imu {
        /// Angular rate \[rad/s\], FLU.
        gyro: [f32; 3],
        /// Specific force \[m/s²\], FLU.
        accel: [f32; 3],
        /// Clock advance \[µs\].
        dt: u16,
    },
    /// An IMU sample 1 ms later, quantised: gyro \[mrad/s\], accel \[cm/s²\].
    ImuQuantised {
        /// Angular rate \[mrad/s\], FLU.
        gyro: [i16; 3],
        /// Specific force \[cm/s²\], FLU.
        accel: [i16; 3],
    },
    /// `n` samples of a level vehicle at rest (gyro 0, accel `+g` along z), 1 ms apart.
    Rest(u8),
    /// A control tick `dt` \[µs\] after the last time, then a telemetry call with `room` bytes.
    Tick {
        /// Clock advance \[µs\].
        dt: u16,
        /// Telemetry buffer length \[bytes\] (mod 2048).
        room: u16,
    },
}
