//! MAVLink 2 over a byte stream: a decoder that takes bytes in chunks of any size and never
//! panics, the conversion of the accepted messages to the controller's frames (through
//! [`crate::frames`], the only place that converts), and the encoder for telemetry.
//!
//! In: `ODOMETRY` (frame `MAV_FRAME_LOCAL_NED` or `MAV_FRAME_LOCAL_FRD`) and `ATT_POS_MOCAP`
//! (pose), `COMMAND_LONG` (`MAV_CMD_COMPONENT_ARM_DISARM` arm/disarm, with param2 =
//! [`FORCE_DISARM_PARAM2`] (21196) a kill, with param1 = 1 and param2 = [`FORCE_ARM_PARAM2`]
//! (2989) an explicit upside-down arm; `MAV_CMD_DO_FLIGHTTERMINATION`
//! kill; `MAV_CMD_NAV_TAKEOFF` with param7 the height above the arming point \[m\] (NaN/0:
//! default); `MAV_CMD_NAV_LAND`; `MAV_CMD_MISSION_START` the helix demo), and
//! `SET_POSITION_TARGET_LOCAL_NED` (frame `MAV_FRAME_LOCAL_NED`, position and yaw; hover
//! target). Out: `HEARTBEAT`, `ATTITUDE_QUATERNION`, `LOCAL_POSITION_NED`, `COMMAND_ACK`,
//! `STATUSTEXT`.
//!
//! With the `hil` feature only (the processor-in-the-loop build, never the flight build), also
//! in: `HIL_SENSOR` (the IMU over the link, body FRD); the pipeline then sends
//! `HIL_ACTUATOR_CONTROLS` and `POSITION_TARGET_LOCAL_NED` every tick.
//!
//! The frame parser is written here (not mavlink's reader) so that it works on a push of
//! bytes with no I/O trait, counts every failure, and resynchronises on the byte after a bad
//! start marker. The payloads are decoded by the `mavlink` crate.

pub use mavlink;

#[cfg(feature = "hil")]
use mavlink::dialects::common::HIL_SENSOR_DATA;
use mavlink::dialects::common::{
    MavCmd, MavFrame, MavMessage, ATT_POS_MOCAP_DATA, COMMAND_LONG_DATA, ODOMETRY_DATA,
    SET_POSITION_TARGET_LOCAL_NED_DATA,
};
use mavlink::{MAVLinkV2MessageRaw, MavHeader, MavlinkVersion, Message, MessageData};
use nalgebra::{Quaternion, Vector3};

use crate::frames;

/// MAVLink 2 start marker.
const STX: u8 = 0xFD;
/// Header bytes after the marker.
const HEADER: usize = 9;
/// Signature length when `incompat_flags & 1`.
const SIGNATURE: usize = 13;
/// Largest frame: marker + header + 255 payload + CRC + signature.
pub const MAX_FRAME: usize = 1 + HEADER + 255 + 2 + SIGNATURE;

/// Where a pose came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PoseSource {
    /// `ODOMETRY`.
    Odometry,
    /// `ATT_POS_MOCAP`.
    Mocap,
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
        }
    }
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
    /// A command with the MAVLink command id to acknowledge.
    Command {
        /// The interpreted command.
        command: Command,
        /// The MAVLink command to acknowledge.
        mav_cmd: MavCmd,
    },
    /// Hover target: position \[m\] NWU and yaw \[rad\] NWU (`None`: keep the current target yaw).
    Setpoint {
        /// Position \[m\], NWU.
        position: Vector3<f32>,
        /// Yaw \[rad\], NWU, if given.
        yaw: Option<f32>,
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
    /// Frames with a valid CRC that were used.
    pub frames_ok: u32,
    /// Valid frames not used: unknown message id, another target, a frame or command not
    /// supported.
    pub frames_dropped: u32,
    /// Frames refused: bad CRC, unknown incompatibility flags, undecodable payload.
    pub frames_malformed: u32,
    /// Bytes skipped while looking for a start marker.
    pub bytes_discarded: u32,
}

/// Result of looking at the head of the buffer.
enum Step {
    /// Nothing to do until the buffer holds this many bytes.
    NeedMore(usize),
    /// Drop `n` bytes from the front; `Some` when they were a frame accepted as this message.
    Consume(usize, Option<Inbound>),
}

/// The MAVLink 2 stream decoder. Holds at most one partial frame ([`MAX_FRAME`] bytes).
#[derive(Clone, Debug)]
pub struct Decoder {
    buf: [u8; MAX_FRAME],
    len: usize,
    /// The buffer length the head frame needs before [`Decoder::poll`] can make progress (0:
    /// look now). Saves re-parsing the header on every byte of a frame.
    need: usize,
    system_id: u8,
    counters: LinkCounters,
}

fn addressed_to_us(target: u8, us: u8) -> bool {
    target == 0 || target == us
}

impl Decoder {
    /// A decoder for a vehicle with MAVLink system id `system_id` (commands and setpoints
    /// addressed to another system are dropped; 0 is broadcast).
    pub fn new(system_id: u8) -> Self {
        Self {
            buf: [0; MAX_FRAME],
            len: 0,
            need: 0,
            system_id,
            counters: LinkCounters::default(),
        }
    }

    /// Counters so far.
    pub fn counters(&self) -> LinkCounters {
        self.counters
    }

    /// Feeds bytes (any chunking); calls `accept` for every message accepted, in order, as soon
    /// as the byte that completes it is in. Nothing is buffered between messages, so a burst of
    /// frames released at once (after a corrupted length byte held them back) loses none.
    pub fn push(&mut self, mut bytes: &[u8], mut accept: impl FnMut(Inbound)) {
        while let (used, Some(m)) = self.feed(bytes) {
            bytes = &bytes[used..];
            accept(m);
        }
    }

    /// Feeds bytes from the front of `bytes` until one completes a message: returns how many
    /// it took and that message, or `(bytes.len(), None)` when all of them completed none.
    /// Call again with the rest after a message. Exactly as [`Decoder::push_byte`] then
    /// [`Decoder::poll`] per byte, but the bytes a frame still needs go in as one copy and its
    /// header is parsed once, not once per byte.
    pub fn feed(&mut self, bytes: &[u8]) -> (usize, Option<Inbound>) {
        let mut used = 0;
        loop {
            if let Some(m) = self.poll() {
                return (used, Some(m));
            }
            let rest = &bytes[used..];
            if rest.is_empty() {
                return (used, None);
            }
            // `poll` cannot progress before `need` bytes; a full buffer (which `poll` always
            // empties in part, since no frame is longer) goes through `push_byte`.
            let n = self
                .need
                .saturating_sub(self.len)
                .max(1)
                .min(MAX_FRAME - self.len)
                .min(rest.len());
            if n == 0 {
                self.push_byte(rest[0]);
                used += 1;
            } else {
                self.buf[self.len..self.len + n].copy_from_slice(&rest[..n]);
                self.len += n;
                used += n;
            }
        }
    }

    /// Feeds one byte of the stream. Drain [`Decoder::poll`] (until `None`) before the next
    /// byte: one byte can release several frames at once. A caller that does not drain loses
    /// the oldest byte when the buffer is full ([`MAX_FRAME`]), counted in `bytes_discarded`,
    /// rather than overflowing.
    pub fn push_byte(&mut self, b: u8) {
        if self.len == MAX_FRAME {
            self.buf.copy_within(1.., 0);
            self.len -= 1;
            self.need = 0;
            self.counters.bytes_discarded = self.counters.bytes_discarded.saturating_add(1);
        }
        self.buf[self.len] = b;
        self.len += 1;
    }

    /// The next message the bytes fed so far complete, in stream order, or `None` when more
    /// bytes are needed. Every frame looked at is counted (ok, dropped, malformed).
    pub fn poll(&mut self) -> Option<Inbound> {
        while self.len > 0 && self.len >= self.need {
            match self.step() {
                Step::NeedMore(n) => {
                    self.need = n;
                    return None;
                }
                Step::Consume(n, message) => {
                    self.need = 0;
                    let n = n.min(self.len);
                    self.buf.copy_within(n..self.len, 0);
                    self.len -= n;
                    if message.is_some() {
                        return message;
                    }
                }
            }
        }
        None
    }

    fn step(&mut self) -> Step {
        let buf = &self.buf[..self.len];
        if buf.is_empty() {
            return Step::NeedMore(1);
        }
        if buf[0] != STX {
            let skip = buf.iter().position(|&b| b == STX).unwrap_or(buf.len());
            self.counters.bytes_discarded =
                self.counters.bytes_discarded.saturating_add(skip as u32);
            return Step::Consume(skip, None);
        }
        if buf.len() < 3 {
            return Step::NeedMore(3);
        }
        let incompat = buf[2];
        if incompat & !0x01 != 0 {
            // Unknown incompatibility flag (e.g. 32-bit system ids): we must not parse it.
            self.counters.frames_malformed += 1;
            return Step::Consume(1, None);
        }
        let payload_len = buf[1] as usize;
        let signed = incompat & 0x01 != 0;
        let total = 1 + HEADER + payload_len + 2 + if signed { SIGNATURE } else { 0 };
        if buf.len() < total {
            return Step::NeedMore(total);
        }
        let msgid = u32::from_le_bytes([buf[7], buf[8], buf[9], 0]);
        let extra = MavMessage::extra_crc(msgid);
        if extra == 0 {
            // Not in the common dialect: its CRC cannot be checked, so it may as well be a
            // false marker inside other data. Skipping only the marker keeps the frames behind
            // it (a real unknown frame is then rescanned, which costs at most a few spurious
            // malformed counts if its payload holds 0xFD).
            self.counters.frames_dropped += 1;
            return Step::Consume(1, None);
        }
        let crc_at = 1 + HEADER + payload_len;
        let crc = u16::from_le_bytes([buf[crc_at], buf[crc_at + 1]]);
        if crate::link_crc::frame_crc(&buf[1..crc_at], extra) != crc {
            self.counters.frames_malformed += 1;
            // A false marker or a corrupted frame: look again from the next byte.
            return Step::Consume(1, None);
        }
        let payload = &buf[1 + HEADER..crc_at];
        let message = match self.interpret(msgid, payload) {
            Interpretation::Accepted(m) => {
                self.counters.frames_ok += 1;
                Some(m)
            }
            Interpretation::Ignored => {
                self.counters.frames_dropped += 1;
                None
            }
            Interpretation::Malformed => {
                self.counters.frames_malformed += 1;
                None
            }
        };
        Step::Consume(total, message)
    }

    fn interpret(&self, msgid: u32, payload: &[u8]) -> Interpretation {
        use mavlink::MessageData;
        let v = MavlinkVersion::V2;
        match msgid {
            ODOMETRY_DATA::ID => match ODOMETRY_DATA::deser(v, payload) {
                Ok(m) => odometry(&m),
                Err(_) => Interpretation::Malformed,
            },
            ATT_POS_MOCAP_DATA::ID => match ATT_POS_MOCAP_DATA::deser(v, payload) {
                Ok(m) => Interpretation::Accepted(Inbound::Pose {
                    position: frames::flip_vector([m.x, m.y, m.z]),
                    attitude: frames::flip_quaternion(m.q),
                    source: PoseSource::Mocap,
                }),
                Err(_) => Interpretation::Malformed,
            },
            COMMAND_LONG_DATA::ID => match COMMAND_LONG_DATA::deser(v, payload) {
                Ok(m) if addressed_to_us(m.target_system, self.system_id) => command(&m),
                Ok(_) => Interpretation::Ignored,
                Err(_) => Interpretation::Malformed,
            },
            SET_POSITION_TARGET_LOCAL_NED_DATA::ID => {
                match SET_POSITION_TARGET_LOCAL_NED_DATA::deser(v, payload) {
                    Ok(m) if addressed_to_us(m.target_system, self.system_id) => setpoint(&m),
                    Ok(_) => Interpretation::Ignored,
                    Err(_) => Interpretation::Malformed,
                }
            }
            #[cfg(feature = "hil")]
            HIL_SENSOR_DATA::ID => match HIL_SENSOR_DATA::deser(v, payload) {
                Ok(m) => hil_sensor(&m),
                Err(_) => Interpretation::Malformed,
            },
            _ => Interpretation::Ignored,
        }
    }
}

#[cfg(feature = "hil")]
fn hil_sensor(m: &HIL_SENSOR_DATA) -> Interpretation {
    if m.fields_updated.bits() & HIL_SENSOR_IMU_FIELDS != HIL_SENSOR_IMU_FIELDS {
        return Interpretation::Ignored;
    }
    // FRD → FLU is the same axis flip as NED → NWU.
    let gyro = frames::flip_vector([m.xgyro, m.ygyro, m.zgyro]);
    let accel = frames::flip_vector([m.xacc, m.yacc, m.zacc]);
    Interpretation::Accepted(Inbound::HilSensor {
        gyro_rad_s: [gyro.x, gyro.y, gyro.z],
        accel_m_s2: [accel.x, accel.y, accel.z],
        time_us: m.time_usec,
    })
}

enum Interpretation {
    Accepted(Inbound),
    Ignored,
    Malformed,
}

fn odometry(m: &ODOMETRY_DATA) -> Interpretation {
    if !matches!(
        m.frame_id,
        MavFrame::MAV_FRAME_LOCAL_NED | MavFrame::MAV_FRAME_LOCAL_FRD
    ) {
        return Interpretation::Ignored;
    }
    Interpretation::Accepted(Inbound::Pose {
        position: frames::flip_vector([m.x, m.y, m.z]),
        attitude: frames::flip_quaternion(m.q),
        source: PoseSource::Odometry,
    })
}

/// `COMMAND_LONG` param2 of `MAV_CMD_COMPONENT_ARM_DISARM` with param1 = 0 that disarms in
/// flight: a kill (PX4's magic number, MAVLink common's "force disarm").
pub const FORCE_DISARM_PARAM2: f32 = 21196.0;
/// `COMMAND_LONG` param2 of `MAV_CMD_COMPONENT_ARM_DISARM` with param1 = 1 that forces the arm
/// (PX4's magic number, MAVLink common's "force arm"); here the explicit permission to arm
/// upside down.
pub const FORCE_ARM_PARAM2: f32 = 2989.0;

fn command(m: &COMMAND_LONG_DATA) -> Interpretation {
    let c = match m.command {
        MavCmd::MAV_CMD_COMPONENT_ARM_DISARM => {
            if m.param1 == 1.0 {
                Command::Arm {
                    inverted: m.param2 == FORCE_ARM_PARAM2,
                }
            } else if m.param1 == 0.0 {
                if m.param2 == FORCE_DISARM_PARAM2 {
                    Command::Kill
                } else {
                    Command::Disarm
                }
            } else {
                return Interpretation::Malformed;
            }
        }
        MavCmd::MAV_CMD_DO_FLIGHTTERMINATION if m.param1 >= 0.5 => Command::Kill,
        MavCmd::MAV_CMD_NAV_TAKEOFF => Command::Takeoff {
            height: (m.param7.is_finite() && m.param7 > 0.0).then_some(m.param7),
        },
        MavCmd::MAV_CMD_NAV_LAND => Command::Land,
        MavCmd::MAV_CMD_MISSION_START => Command::StartHelix,
        _ => return Interpretation::Ignored,
    };
    Interpretation::Accepted(Inbound::Command {
        command: c,
        mav_cmd: m.command,
    })
}

fn setpoint(m: &SET_POSITION_TARGET_LOCAL_NED_DATA) -> Interpretation {
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
    Interpretation::Accepted(Inbound::Setpoint { position, yaw })
}

/// Encodes `message` as a MAVLink 2 frame from (`system_id`, `component_id`) with `sequence`
/// into `out`. Returns the number of bytes written, 0 if `out` is too small (nothing written).
pub fn encode(
    message: &MavMessage,
    system_id: u8,
    component_id: u8,
    sequence: u8,
    out: &mut [u8],
) -> usize {
    let mut raw = MAVLinkV2MessageRaw::new();
    raw.serialize_message(header(system_id, component_id, sequence), message);
    copy_out(raw.raw_bytes(), out)
}

/// [`encode`] for one message type: links only that message's serializer (the firmware uses
/// this; `MavMessage::ser` matches over every message of the dialect, ~27 KiB of flash).
pub fn encode_data<D: MessageData>(
    message: &D,
    system_id: u8,
    component_id: u8,
    sequence: u8,
    out: &mut [u8],
) -> usize {
    let mut raw = MAVLinkV2MessageRaw::new();
    raw.serialize_message_data(header(system_id, component_id, sequence), message);
    copy_out(raw.raw_bytes(), out)
}

fn header(system_id: u8, component_id: u8, sequence: u8) -> MavHeader {
    MavHeader {
        system_id: u32::from(system_id),
        component_id,
        sequence,
    }
}

fn copy_out(bytes: &[u8], out: &mut [u8]) -> usize {
    if bytes.len() > out.len() {
        return 0;
    }
    out[..bytes.len()].copy_from_slice(bytes);
    bytes.len()
}

#[cfg(test)]
mod tests {
    use super::*;
    use mavlink::dialects::common::{PositionTargetTypemask, HEARTBEAT_DATA};

    fn frame(m: &MavMessage, seq: u8) -> ([u8; MAX_FRAME], usize) {
        let mut out = [0u8; MAX_FRAME];
        let n = encode(m, 200, 1, seq, &mut out);
        assert!(n > 0);
        (out, n)
    }

    fn mocap(x: f32) -> MavMessage {
        MavMessage::ATT_POS_MOCAP(ATT_POS_MOCAP_DATA {
            time_usec: 0,
            q: [1.0, 0.0, 0.0, 0.0],
            x,
            y: 2.0,
            z: -3.0,
        })
    }

    fn collect(d: &mut Decoder, bytes: &[u8]) -> Vec<Inbound> {
        let mut v = Vec::new();
        d.push(bytes, |m| v.push(m));
        v
    }

    /// A pose in NED arrives in NWU; byte-by-byte and whole-frame pushes agree.
    #[test]
    fn pose_in_any_chunking() {
        let (f, n) = frame(&mocap(1.0), 0);
        for chunk in [1usize, 2, 3, 7, 64, 280] {
            let mut d = Decoder::new(1);
            let mut got = Vec::new();
            for c in f[..n].chunks(chunk) {
                got.extend(collect(&mut d, c));
            }
            assert_eq!(got.len(), 1, "chunk {chunk}");
            match got[0] {
                Inbound::Pose { position, .. } => {
                    assert_eq!(position, Vector3::new(1.0, -2.0, 3.0))
                }
                _ => panic!(),
            }
            assert_eq!(d.counters().frames_ok, 1);
        }
    }

    /// Garbage before, a corrupted frame, then a good one: the good one survives; counters say
    /// what happened.
    #[test]
    fn resynchronises_after_garbage_and_corruption() {
        let (good, n) = frame(&mocap(4.0), 1);
        let mut bad = good;
        bad[15] ^= 0x55;
        let mut stream = Vec::new();
        stream.extend_from_slice(&[1, 2, 3, STX, 9]);
        stream.extend_from_slice(&bad[..n]);
        stream.extend_from_slice(&good[..n - 5]); // truncated
        stream.extend_from_slice(&good[..n]);
        let mut d = Decoder::new(1);
        let got = collect(&mut d, &stream);
        assert_eq!(got.len(), 1);
        let c = d.counters();
        assert_eq!(c.frames_ok, 1);
        assert!(c.frames_malformed >= 2, "{c:?}");
        assert!(c.bytes_discarded >= 3);
    }

    /// Commands: arm, inverted arm, kill (21196 and flight termination), takeoff height, land,
    /// mission start; another target is dropped.
    #[test]
    fn commands() {
        let cmd = |command, p1: f32, p2: f32, p7: f32, target: u8| {
            MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
                param1: p1,
                param2: p2,
                param7: p7,
                command,
                target_system: target,
                ..Default::default()
            })
        };
        use MavCmd::*;
        let cases = [
            (
                cmd(MAV_CMD_COMPONENT_ARM_DISARM, 1.0, 0.0, 0.0, 1),
                Some(Command::Arm { inverted: false }),
            ),
            (
                cmd(MAV_CMD_COMPONENT_ARM_DISARM, 1.0, FORCE_ARM_PARAM2, 0.0, 0),
                Some(Command::Arm { inverted: true }),
            ),
            (
                cmd(MAV_CMD_COMPONENT_ARM_DISARM, 0.0, 0.0, 0.0, 1),
                Some(Command::Disarm),
            ),
            (
                cmd(
                    MAV_CMD_COMPONENT_ARM_DISARM,
                    0.0,
                    FORCE_DISARM_PARAM2,
                    0.0,
                    1,
                ),
                Some(Command::Kill),
            ),
            (
                cmd(MAV_CMD_DO_FLIGHTTERMINATION, 1.0, 0.0, 0.0, 1),
                Some(Command::Kill),
            ),
            (
                cmd(MAV_CMD_NAV_TAKEOFF, 0.0, 0.0, 1.5, 1),
                Some(Command::Takeoff { height: Some(1.5) }),
            ),
            (
                cmd(MAV_CMD_NAV_TAKEOFF, 0.0, 0.0, f32::NAN, 1),
                Some(Command::Takeoff { height: None }),
            ),
            (cmd(MAV_CMD_NAV_LAND, 0.0, 0.0, 0.0, 1), Some(Command::Land)),
            (
                cmd(MAV_CMD_MISSION_START, 0.0, 0.0, 0.0, 1),
                Some(Command::StartHelix),
            ),
            (cmd(MAV_CMD_COMPONENT_ARM_DISARM, 1.0, 0.0, 0.0, 7), None),
        ];
        for (m, want) in cases {
            let (f, n) = frame(&m, 0);
            let mut d = Decoder::new(1);
            let got = collect(&mut d, &f[..n]);
            match want {
                Some(c) => {
                    assert_eq!(got.len(), 1);
                    assert!(matches!(got[0], Inbound::Command { command, .. } if command == c));
                }
                None => {
                    assert!(got.is_empty());
                    assert_eq!(d.counters().frames_dropped, 1);
                }
            }
        }
    }

    /// A NED setpoint 2 m up facing east is z = +2 m, yaw −90° in NWU.
    #[test]
    fn setpoint_conversion() {
        let m = MavMessage::SET_POSITION_TARGET_LOCAL_NED(SET_POSITION_TARGET_LOCAL_NED_DATA {
            x: 1.0,
            y: 0.5,
            z: -2.0,
            yaw: core::f32::consts::FRAC_PI_2,
            type_mask: PositionTargetTypemask::empty(),
            target_system: 1,
            coordinate_frame: MavFrame::MAV_FRAME_LOCAL_NED,
            ..Default::default()
        });
        let (f, n) = frame(&m, 0);
        let got = collect(&mut Decoder::new(1), &f[..n]);
        match got[0] {
            Inbound::Setpoint { position, yaw } => {
                assert_eq!(position, Vector3::new(1.0, -0.5, 2.0));
                assert!((yaw.unwrap() + core::f32::consts::FRAC_PI_2).abs() < 1e-6);
            }
            _ => panic!(),
        }
    }

    /// Messages we do not use are counted as dropped, not malformed.
    #[test]
    fn unused_messages_are_dropped() {
        let (f, n) = frame(&MavMessage::HEARTBEAT(HEARTBEAT_DATA::default()), 0);
        let mut d = Decoder::new(1);
        assert!(collect(&mut d, &f[..n]).is_empty());
        assert_eq!(d.counters().frames_dropped, 1);
        assert_eq!(d.counters().frames_malformed, 0);
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(512))]
        /// `push` (whole runs of bytes through `feed`) gives the same messages, in the same
        /// order, and the same counters as the byte-at-a-time `push_byte` + `poll` loop, for
        /// any mix of valid frames, frames with one corrupted byte (length bytes included) and
        /// junk, in any chunking.
        #[test]
        fn feed_equals_byte_by_byte(
            pieces in proptest::collection::vec(
                (0u8..3, -1e3f32..1e3, proptest::collection::vec(proptest::prelude::any::<u8>(), 0..40),
                 0usize..48, proptest::prelude::any::<u8>()),
                1..12,
            ),
            chunk in 1usize..70,
        ) {
            let mut stream = Vec::new();
            for (seq, (kind, x, junk, at, flip)) in pieces.into_iter().enumerate() {
                let (mut f, n) = frame(&mocap(x), seq as u8);
                match kind {
                    0 => {}
                    1 => f[at % n] ^= flip | 1,
                    _ => stream.extend_from_slice(&junk),
                }
                stream.extend_from_slice(&f[..n]);
            }
            let mut bytewise = Decoder::new(1);
            let mut want = Vec::new();
            for &b in &stream {
                bytewise.push_byte(b);
                while let Some(m) = bytewise.poll() {
                    want.push(m);
                }
            }
            let mut fed = Decoder::new(1);
            let mut got = Vec::new();
            for c in stream.chunks(chunk) {
                got.extend(collect(&mut fed, c));
            }
            proptest::prop_assert_eq!(got, want);
            proptest::prop_assert_eq!(fed.counters(), bytewise.counters());
            proptest::prop_assert_eq!(&fed.buf[..fed.len], &bytewise.buf[..bytewise.len]);
        }
    }

    /// Encoding into a buffer that is too small writes nothing.
    #[test]
    fn encode_too_small() {
        let mut small = [0u8; 10];
        assert_eq!(encode(&mocap(0.0), 1, 1, 0, &mut small), 0);
    }

    /// A caller that feeds bytes without draining `poll` never overflows the buffer: the
    /// oldest bytes go, counted; a frame pushed and drained afterwards still decodes.
    #[test]
    fn undrained_pushes_discard_the_oldest_bytes_counted() {
        let mut d = Decoder::new(1);
        let (f, n) = frame(&mocap(1.0), 0);
        // A claimed 255-byte payload keeps the decoder waiting for MAX_FRAME bytes.
        let mut junk = f;
        junk[1] = 255;
        for &b in junk[..n].iter().chain([0u8; MAX_FRAME].iter()) {
            d.push_byte(b);
        }
        assert!(d.counters().bytes_discarded >= 1);
        while d.poll().is_some() {}
        let got = collect(&mut d, &f[..n]);
        assert_eq!(got.len(), 1);
    }
}
