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

use firmware::link;
use firmware::link::mavlink::dialects::common::{
    HilSensorUpdatedFlags, MavCmd, MavFrame, MavMessage, MavMissionResult, PositionTargetTypemask,
    ATT_POS_MOCAP_DATA, COMMAND_LONG_DATA, HIL_SENSOR_DATA, MISSION_ACK_DATA,
    MISSION_CLEAR_ALL_DATA, MISSION_COUNT_DATA, MISSION_ITEM_INT_DATA, MISSION_REQUEST_INT_DATA,
    MISSION_REQUEST_LIST_DATA, ODOMETRY_DATA, SET_POSITION_TARGET_LOCAL_NED_DATA,
};

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

/// Reads fields from the input; past its end every byte is 0.
struct Reader<'a> {
    data: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    fn done(&self) -> bool {
        self.at >= self.data.len()
    }
    fn u8(&mut self) -> u8 {
        let b = self.data.get(self.at).copied().unwrap_or(0);
        self.at += 1;
        b
    }
    fn array<const N: usize>(&mut self) -> [u8; N] {
        let mut a = [0u8; N];
        for b in a.iter_mut() {
            *b = self.u8();
        }
        a
    }
    fn u16(&mut self) -> u16 {
        u16::from_le_bytes(self.array())
    }
    fn i16(&mut self) -> i16 {
        i16::from_le_bytes(self.array())
    }
    fn u32(&mut self) -> u32 {
        u32::from_le_bytes(self.array())
    }
    fn i32(&mut self) -> i32 {
        i32::from_le_bytes(self.array())
    }
    fn f32(&mut self) -> f32 {
        f32::from_le_bytes(self.array())
    }
    fn f32s<const N: usize>(&mut self) -> [f32; N] {
        let mut a = [0.0; N];
        for x in a.iter_mut() {
            *x = self.f32();
        }
        a
    }
    fn i16s<const N: usize>(&mut self) -> [i16; N] {
        let mut a = [0; N];
        for x in a.iter_mut() {
            *x = self.i16();
        }
        a
    }
}

/// Reads the whole input as operations (never fails: see the module's table).
pub fn parse(data: &[u8]) -> Vec<Op> {
    let mut r = Reader { data, at: 0 };
    let mut ops = Vec::new();
    while !r.done() {
        let op = match r.u8() % 6 {
            0 => {
                let n = usize::from(r.u8());
                let end = (r.at + n).min(data.len());
                let bytes = data.get(r.at..end).unwrap_or(&[]).to_vec();
                r.at += n;
                Op::Bytes(bytes)
            }
            1 => {
                let spec = match r.u8() % 6 {
                    0 => FrameSpec::Mocap {
                        position: r.f32s(),
                        q: r.f32s(),
                    },
                    1 => FrameSpec::Odometry {
                        frame: r.u8(),
                        position: r.f32s(),
                        q: r.f32s(),
                    },
                    2 => FrameSpec::Command {
                        command: r.u8(),
                        target: r.u8(),
                        params: r.f32s(),
                    },
                    3 => FrameSpec::Setpoint {
                        frame: r.u8(),
                        mask: r.u16(),
                        target: r.u8(),
                        position: r.f32s(),
                        yaw: r.f32(),
                    },
                    4 => FrameSpec::HilSensor {
                        fields: r.u32(),
                        accel: r.f32s(),
                        gyro: r.f32s(),
                        time_offset_us: r.i32(),
                    },
                    _ => {
                        let sub = r.u8() % 9;
                        let target = r.u8();
                        let message = match sub {
                            0 => MissionSpec::Count { count: r.u16() },
                            1 => MissionSpec::ItemInt {
                                seq: r.u16(),
                                command: r.u8(),
                                frame: r.u8(),
                                xy: [r.i32(), r.i32()],
                                z: r.f32(),
                                params: r.f32s(),
                            },
                            2 => MissionSpec::Item {
                                seq: r.u16(),
                                command: r.u8(),
                                frame: r.u8(),
                                xy: r.f32s(),
                                z: r.f32(),
                                params: r.f32s(),
                            },
                            3 => MissionSpec::RequestInt { seq: r.u16() },
                            4 => MissionSpec::RequestList,
                            5 => MissionSpec::ClearAll,
                            6 => MissionSpec::SetCurrent { seq: r.u16() },
                            7 => MissionSpec::Ack { result: r.u8() },
                            _ => MissionSpec::SetOrigin {
                                lla: [r.i32(), r.i32(), r.i32()],
                            },
                        };
                        FrameSpec::Mission { target, message }
                    }
                };
                Op::Frame {
                    spec,
                    chunk: r.u8() % 64 + 1,
                }
            }
            2 => Op::Imu {
                gyro: r.f32s(),
                accel: r.f32s(),
                dt: r.u16(),
            },
            3 => Op::ImuQuantised {
                gyro: r.i16s(),
                accel: r.i16s(),
            },
            4 => Op::Rest(r.u8()),
            _ => Op::Tick {
                dt: r.u16(),
                room: r.u16() % 2048,
            },
        };
        ops.push(op);
    }
    ops
}

fn put_f32s(out: &mut Vec<u8>, xs: &[f32]) {
    for x in xs {
        out.extend_from_slice(&x.to_le_bytes());
    }
}

/// Writes a [`FrameSpec::Mission`] after the kind byte's place: kind 5, sub-kind, target, fields.
fn put_mission(out: &mut Vec<u8>, target: u8, m: &MissionSpec) {
    let sub = match m {
        MissionSpec::Count { .. } => 0,
        MissionSpec::ItemInt { .. } => 1,
        MissionSpec::Item { .. } => 2,
        MissionSpec::RequestInt { .. } => 3,
        MissionSpec::RequestList => 4,
        MissionSpec::ClearAll => 5,
        MissionSpec::SetCurrent { .. } => 6,
        MissionSpec::Ack { .. } => 7,
        MissionSpec::SetOrigin { .. } => 8,
    };
    out.extend_from_slice(&[5, sub, target]);
    match m {
        MissionSpec::Count { count: n }
        | MissionSpec::RequestInt { seq: n }
        | MissionSpec::SetCurrent { seq: n } => out.extend_from_slice(&n.to_le_bytes()),
        MissionSpec::ItemInt {
            seq,
            command,
            frame,
            xy,
            z,
            params,
        } => {
            out.extend_from_slice(&seq.to_le_bytes());
            out.extend_from_slice(&[*command, *frame]);
            for v in xy {
                out.extend_from_slice(&v.to_le_bytes());
            }
            put_f32s(out, &[*z]);
            put_f32s(out, params);
        }
        MissionSpec::Item {
            seq,
            command,
            frame,
            xy,
            z,
            params,
        } => {
            out.extend_from_slice(&seq.to_le_bytes());
            out.extend_from_slice(&[*command, *frame]);
            put_f32s(out, xy);
            put_f32s(out, &[*z]);
            put_f32s(out, params);
        }
        MissionSpec::RequestList | MissionSpec::ClearAll => {}
        MissionSpec::Ack { result } => out.push(*result),
        MissionSpec::SetOrigin { lla } => {
            for v in lla {
                out.extend_from_slice(&v.to_le_bytes());
            }
        }
    }
}

/// Writes operations in the format [`parse`] reads (`parse(&encode(ops)) == ops` for ops whose
/// fields are in range: at most 255 raw bytes, `chunk` in 1..=64, `room` < 2048).
pub fn encode(ops: &[Op]) -> Vec<u8> {
    let mut out = Vec::new();
    for op in ops {
        match op {
            Op::Bytes(b) => {
                out.push(0);
                out.push(b.len().min(255) as u8);
                out.extend_from_slice(&b[..b.len().min(255)]);
            }
            Op::Frame { spec, chunk } => {
                out.push(1);
                match spec {
                    FrameSpec::Mocap { position, q } => {
                        out.push(0);
                        put_f32s(&mut out, position);
                        put_f32s(&mut out, q);
                    }
                    FrameSpec::Odometry { frame, position, q } => {
                        out.push(1);
                        out.push(*frame);
                        put_f32s(&mut out, position);
                        put_f32s(&mut out, q);
                    }
                    FrameSpec::Command {
                        command,
                        target,
                        params,
                    } => {
                        out.extend_from_slice(&[2, *command, *target]);
                        put_f32s(&mut out, params);
                    }
                    FrameSpec::Setpoint {
                        frame,
                        mask,
                        target,
                        position,
                        yaw,
                    } => {
                        out.extend_from_slice(&[3, *frame]);
                        out.extend_from_slice(&mask.to_le_bytes());
                        out.push(*target);
                        put_f32s(&mut out, position);
                        put_f32s(&mut out, &[*yaw]);
                    }
                    FrameSpec::HilSensor {
                        fields,
                        accel,
                        gyro,
                        time_offset_us,
                    } => {
                        out.push(4);
                        out.extend_from_slice(&fields.to_le_bytes());
                        put_f32s(&mut out, accel);
                        put_f32s(&mut out, gyro);
                        out.extend_from_slice(&time_offset_us.to_le_bytes());
                    }
                    FrameSpec::Mission { target, message } => {
                        put_mission(&mut out, *target, message)
                    }
                }
                out.push(chunk.wrapping_sub(1) % 64);
            }
            Op::Imu { gyro, accel, dt } => {
                out.push(2);
                put_f32s(&mut out, gyro);
                put_f32s(&mut out, accel);
                out.extend_from_slice(&dt.to_le_bytes());
            }
            Op::ImuQuantised { gyro, accel } => {
                out.push(3);
                for x in gyro.iter().chain(accel) {
                    out.extend_from_slice(&x.to_le_bytes());
                }
            }
            Op::Rest(n) => out.extend_from_slice(&[4, *n]),
            Op::Tick { dt, room } => {
                out.push(5);
                out.extend_from_slice(&dt.to_le_bytes());
                out.extend_from_slice(&(room % 2048).to_le_bytes());
            }
        }
    }
    out
}

fn mav_frame(n: u8) -> MavFrame {
    use firmware::link::mavlink::dialects::common::MavFrame as F;
    match n {
        0 => F::MAV_FRAME_GLOBAL,
        1 => F::MAV_FRAME_LOCAL_NED,
        7 => F::MAV_FRAME_LOCAL_OFFSET_NED,
        12 => F::MAV_FRAME_BODY_FRD,
        20 => F::MAV_FRAME_LOCAL_FRD,
        21 => F::MAV_FRAME_LOCAL_FLU,
        _ => F::MAV_FRAME_LOCAL_NED,
    }
}

/// A mission item's `frame`: [`mav_frame`]'s (0 is `MAV_FRAME_GLOBAL`, most numbers
/// `MAV_FRAME_LOCAL_NED`), and 3, 5, 6 the other global frames ground stations send
/// (`GLOBAL_RELATIVE_ALT`, `GLOBAL_INT`, `GLOBAL_RELATIVE_ALT_INT`), which the firmware refuses.
// The `_INT` frames are deprecated (superseded by their plain names) but older ground stations
// still send them in mission items, and the firmware's global-frame check names them.
#[allow(deprecated)]
pub fn mission_frame(n: u8) -> MavFrame {
    match n {
        3 => MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT,
        5 => MavFrame::MAV_FRAME_GLOBAL_INT,
        6 => MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT,
        _ => mav_frame(n),
    }
}

/// The `MISSION_*` message of a [`FrameSpec::Mission`] for system `target` (component 0).
// MISSION_ITEM and MISSION_SET_CURRENT are deprecated in MAVLink's common set, but ground
// stations still send them (MAVProxy's wp module, older QGroundControl) and the firmware
// interprets them: the fuzzer must send them too.
#[allow(deprecated)]
fn mission_message(target: u8, m: &MissionSpec) -> MavMessage {
    use firmware::link::mavlink::dialects::common::{MISSION_ITEM_DATA, MISSION_SET_CURRENT_DATA};
    let command = |i: u8| MISSION_COMMANDS[usize::from(i) % MISSION_COMMANDS.len()];
    match m {
        MissionSpec::Count { count } => MavMessage::MISSION_COUNT(MISSION_COUNT_DATA {
            count: *count,
            target_system: target,
            ..Default::default()
        }),
        MissionSpec::ItemInt {
            seq,
            command: c,
            frame,
            xy,
            z,
            params,
        } => MavMessage::MISSION_ITEM_INT(MISSION_ITEM_INT_DATA {
            param1: params[0],
            param2: params[1],
            param3: params[2],
            param4: params[3],
            x: xy[0],
            y: xy[1],
            z: *z,
            seq: *seq,
            command: command(*c),
            target_system: target,
            frame: mission_frame(*frame),
            autocontinue: 1,
            ..Default::default()
        }),
        MissionSpec::Item {
            seq,
            command: c,
            frame,
            xy,
            z,
            params,
        } => MavMessage::MISSION_ITEM(MISSION_ITEM_DATA {
            param1: params[0],
            param2: params[1],
            param3: params[2],
            param4: params[3],
            x: xy[0],
            y: xy[1],
            z: *z,
            seq: *seq,
            command: command(*c),
            target_system: target,
            frame: mission_frame(*frame),
            autocontinue: 1,
            ..Default::default()
        }),
        MissionSpec::RequestInt { seq } => {
            MavMessage::MISSION_REQUEST_INT(MISSION_REQUEST_INT_DATA {
                seq: *seq,
                target_system: target,
                ..Default::default()
            })
        }
        MissionSpec::RequestList => MavMessage::MISSION_REQUEST_LIST(MISSION_REQUEST_LIST_DATA {
            target_system: target,
            ..Default::default()
        }),
        MissionSpec::ClearAll => MavMessage::MISSION_CLEAR_ALL(MISSION_CLEAR_ALL_DATA {
            target_system: target,
            ..Default::default()
        }),
        MissionSpec::SetCurrent { seq } => {
            MavMessage::MISSION_SET_CURRENT(MISSION_SET_CURRENT_DATA {
                seq: *seq,
                target_system: target,
                ..Default::default()
            })
        }
        MissionSpec::Ack { result } => MavMessage::MISSION_ACK(MISSION_ACK_DATA {
            target_system: target,
            mavtype: MISSION_RESULTS[usize::from(*result) % MISSION_RESULTS.len()],
            ..Default::default()
        }),
        MissionSpec::SetOrigin { lla } => MavMessage::SET_GPS_GLOBAL_ORIGIN(
            firmware::link::mavlink::dialects::common::SET_GPS_GLOBAL_ORIGIN_DATA {
                latitude: lla[0],
                longitude: lla[1],
                altitude: lla[2],
                target_system: target,
            },
        ),
    }
}

/// The MAVLink message of a [`FrameSpec`] at the script's clock `now_us` \[µs\].
pub fn message(spec: &FrameSpec, now_us: u64) -> MavMessage {
    match spec {
        FrameSpec::Mocap { position, q } => MavMessage::ATT_POS_MOCAP(ATT_POS_MOCAP_DATA {
            time_usec: now_us,
            q: *q,
            x: position[0],
            y: position[1],
            z: position[2],
        }),
        FrameSpec::Odometry { frame, position, q } => MavMessage::ODOMETRY(ODOMETRY_DATA {
            time_usec: now_us,
            x: position[0],
            y: position[1],
            z: position[2],
            q: *q,
            vx: f32::NAN,
            vy: f32::NAN,
            vz: f32::NAN,
            frame_id: mav_frame(*frame),
            child_frame_id: MavFrame::MAV_FRAME_BODY_FRD,
            ..Default::default()
        }),
        FrameSpec::Command {
            command,
            target,
            params,
        } => MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
            param1: params[0],
            param2: params[1],
            param7: params[2],
            command: COMMANDS[usize::from(*command) % COMMANDS.len()],
            target_system: *target,
            ..Default::default()
        }),
        FrameSpec::Setpoint {
            frame,
            mask,
            target,
            position,
            yaw,
        } => MavMessage::SET_POSITION_TARGET_LOCAL_NED(SET_POSITION_TARGET_LOCAL_NED_DATA {
            time_boot_ms: (now_us / 1000) as u32,
            x: position[0],
            y: position[1],
            z: position[2],
            yaw: *yaw,
            type_mask: PositionTargetTypemask::from_bits_retain(*mask),
            target_system: *target,
            coordinate_frame: mav_frame(*frame),
            ..Default::default()
        }),
        FrameSpec::HilSensor {
            fields,
            accel,
            gyro,
            time_offset_us,
        } => MavMessage::HIL_SENSOR(HIL_SENSOR_DATA {
            time_usec: now_us.saturating_add_signed(i64::from(*time_offset_us)),
            xacc: accel[0],
            yacc: accel[1],
            zacc: accel[2],
            xgyro: gyro[0],
            ygyro: gyro[1],
            zgyro: gyro[2],
            fields_updated: HilSensorUpdatedFlags::from_bits_retain(*fields),
            ..Default::default()
        }),
        FrameSpec::Mission { target, message } => mission_message(*target, message),
    }
}

/// The bytes of one frame of `spec` at `now_us`, from system 255 (the ground station).
pub fn frame_bytes(spec: &FrameSpec, now_us: u64, sequence: u8) -> Vec<u8> {
    let mut buf = [0u8; link::MAX_FRAME];
    let n = link::encode(&message(spec, now_us), 255, 190, sequence, &mut buf);
    buf[..n].to_vec()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Encoding then parsing gives the operations back, one of each kind.
    #[test]
    fn encode_parse_round_trip() {
        let ops = vec![
            Op::Bytes(vec![0xFD, 1, 2, 3]),
            Op::Frame {
                spec: FrameSpec::Mocap {
                    position: [1.0, -2.0, 0.5],
                    q: [1.0, 0.0, 0.0, 0.0],
                },
                chunk: 64,
            },
            Op::Frame {
                spec: FrameSpec::Odometry {
                    frame: 20,
                    position: [0.0; 3],
                    q: [0.5; 4],
                },
                chunk: 1,
            },
            Op::Frame {
                spec: FrameSpec::Command {
                    command: 2,
                    target: 1,
                    params: [0.0, f32::INFINITY, 1.0],
                },
                chunk: 7,
            },
            Op::Frame {
                spec: FrameSpec::Setpoint {
                    frame: 1,
                    mask: 0x0DF8,
                    target: 0,
                    position: [0.0, 1.0, -1.0],
                    yaw: 0.3,
                },
                chunk: 33,
            },
            Op::Frame {
                spec: FrameSpec::HilSensor {
                    fields: 0x3F,
                    accel: [0.0, 0.0, -9.81],
                    gyro: [0.01, 0.0, 0.0],
                    time_offset_us: -5,
                },
                chunk: 12,
            },
            Op::Frame {
                spec: FrameSpec::Mission {
                    target: 1,
                    message: MissionSpec::Count { count: 2 },
                },
                chunk: 64,
            },
            Op::Frame {
                spec: FrameSpec::Mission {
                    target: 1,
                    message: MissionSpec::ItemInt {
                        seq: 0,
                        command: 1,
                        frame: 1,
                        xy: [12_345, -7],
                        z: -1.5,
                        params: [0.0, 0.2, f32::NEG_INFINITY, 90.0],
                    },
                },
                chunk: 5,
            },
            Op::Frame {
                spec: FrameSpec::Mission {
                    target: 0,
                    message: MissionSpec::Item {
                        seq: 1,
                        command: 3,
                        frame: 5,
                        xy: [47.5, 8.25],
                        z: 10.0,
                        params: [1.0, 0.0, 0.0, f32::INFINITY],
                    },
                },
                chunk: 17,
            },
            Op::Frame {
                spec: FrameSpec::Mission {
                    target: 1,
                    message: MissionSpec::RequestInt { seq: 65_535 },
                },
                chunk: 2,
            },
            Op::Frame {
                spec: FrameSpec::Mission {
                    target: 1,
                    message: MissionSpec::RequestList,
                },
                chunk: 64,
            },
            Op::Frame {
                spec: FrameSpec::Mission {
                    target: 9,
                    message: MissionSpec::ClearAll,
                },
                chunk: 1,
            },
            Op::Frame {
                spec: FrameSpec::Mission {
                    target: 1,
                    message: MissionSpec::SetCurrent { seq: 1 },
                },
                chunk: 40,
            },
            Op::Frame {
                spec: FrameSpec::Mission {
                    target: 1,
                    message: MissionSpec::Ack { result: 3 },
                },
                chunk: 64,
            },
            Op::Frame {
                spec: FrameSpec::Mission {
                    target: 1,
                    message: MissionSpec::SetOrigin {
                        lla: [470_000_000, -80_000_000, 400_000],
                    },
                },
                chunk: 17,
            },
            Op::Imu {
                gyro: [0.1, 0.2, 0.3],
                accel: [0.0, 0.0, 9.81],
                dt: 999,
            },
            Op::ImuQuantised {
                gyro: [-3, 0, 7],
                accel: [0, 1, 981],
            },
            Op::Rest(200),
            Op::Tick {
                dt: 10_000,
                room: 1024,
            },
        ];
        assert_eq!(parse(&encode(&ops)), ops);
    }

    /// Every mission sub-kind becomes its own `MISSION_*` message, with the target system, the
    /// item's command and frame as chosen.
    #[test]
    #[allow(deprecated)]
    fn mission_specs_map_to_their_messages() {
        let item = |int: bool| {
            let (seq, command, frame, z, params) = (3, 2, 0, -4.0, [1.0, 2.0, 3.0, 4.0]);
            FrameSpec::Mission {
                target: 1,
                message: if int {
                    MissionSpec::ItemInt {
                        seq,
                        command,
                        frame,
                        xy: [10_000, 20_000],
                        z,
                        params,
                    }
                } else {
                    MissionSpec::Item {
                        seq,
                        command,
                        frame,
                        xy: [1.0, 2.0],
                        z,
                        params,
                    }
                },
            }
        };
        match message(&item(true), 0) {
            MavMessage::MISSION_ITEM_INT(m) => {
                assert_eq!((m.seq, m.x, m.y, m.z), (3, 10_000, 20_000, -4.0));
                assert_eq!(m.command, MavCmd::MAV_CMD_NAV_LAND);
                assert_eq!(m.frame, MavFrame::MAV_FRAME_GLOBAL);
                assert_eq!(m.param4, 4.0);
                assert_eq!(m.target_system, 1);
            }
            m => panic!("{m:?}"),
        }
        assert!(matches!(
            message(&item(false), 0),
            MavMessage::MISSION_ITEM(m) if m.x == 1.0 && m.command == MavCmd::MAV_CMD_NAV_LAND
        ));
        let of = |message| crate::script::message(&FrameSpec::Mission { target: 7, message }, 0);
        assert!(matches!(of(MissionSpec::Count { count: 9 }),
            MavMessage::MISSION_COUNT(m) if m.count == 9 && m.target_system == 7));
        assert!(matches!(of(MissionSpec::RequestInt { seq: 4 }),
            MavMessage::MISSION_REQUEST_INT(m) if m.seq == 4 && m.target_system == 7));
        assert!(matches!(of(MissionSpec::RequestList),
            MavMessage::MISSION_REQUEST_LIST(m) if m.target_system == 7));
        assert!(matches!(of(MissionSpec::ClearAll),
            MavMessage::MISSION_CLEAR_ALL(m) if m.target_system == 7));
        assert!(matches!(of(MissionSpec::SetCurrent { seq: 2 }),
            MavMessage::MISSION_SET_CURRENT(m) if m.seq == 2 && m.target_system == 7));
        assert!(matches!(of(MissionSpec::Ack { result: 3 }),
            MavMessage::MISSION_ACK(m) if m.mavtype == MavMissionResult::MAV_MISSION_OPERATION_CANCELLED));
        assert!(matches!(of(MissionSpec::SetOrigin { lla: [1, -2, 3] }),
            MavMessage::SET_GPS_GLOBAL_ORIGIN(m)
                if (m.latitude, m.longitude, m.altitude, m.target_system) == (1, -2, 3, 7)));
    }

    /// A truncated input still parses: the missing bytes read as 0.
    #[test]
    fn truncated_fields_read_as_zero() {
        assert_eq!(parse(&[5, 0x10]), [Op::Tick { dt: 0x10, room: 0 }]);
        assert_eq!(parse(&[0, 9, 1, 2]), [Op::Bytes(vec![1, 2])]);
    }
}
