//! The MAVLink pieces of the processor-in-the-loop protocol: the `HIL_SENSOR` frame the host
//! sends every millisecond, a reader that splits the firmware's serial output into messages,
//! and the decoding of its `HIL_ACTUATOR_CONTROLS` and `POSITION_TARGET_LOCAL_NED`.
//!
//! Frames: the simulation's IMU sample is body FLU and its positions NWU; MAVLink is body FRD
//! and NED. Both maps are `(x, y, z) ↦ (x, −y, −z)` (`firmware::frames`).

use firmware::frames;
use firmware::link::mavlink::dialects::common::{
    HilSensorUpdatedFlags, MavMessage, MavModeFlag, HIL_ACTUATOR_CONTROLS_DATA, HIL_SENSOR_DATA,
    POSITION_TARGET_LOCAL_NED_DATA,
};
use firmware::link::mavlink::{MAVLinkV2MessageRaw, MavHeader, MavlinkVersion, Message};
use firmware::pipeline::ImuSample;
use nalgebra::Vector3;

/// `HIL_SENSOR.fields_updated` of the host's samples: accelerometer x, y, z and gyro x, y, z
/// (bits 0–5).
pub const IMU_FIELDS: u32 = 0b11_1111;

/// The `HIL_SENSOR` (#107) message of an IMU sample: `time_usec` = the sample time \[µs\],
/// accelerometer [m/s²] and gyro [rad/s] converted from body FLU to FRD, `fields_updated` =
/// [`IMU_FIELDS`], every other field 0.
pub fn hil_sensor(sample: &ImuSample) -> MavMessage {
    let [xacc, yacc, zacc] = frames::flip_to_array(&Vector3::from(sample.accel_m_s2));
    let [xgyro, ygyro, zgyro] = frames::flip_to_array(&Vector3::from(sample.gyro_rad_s));
    MavMessage::HIL_SENSOR(HIL_SENSOR_DATA {
        time_usec: sample.time_us,
        xacc,
        yacc,
        zacc,
        xgyro,
        ygyro,
        zgyro,
        fields_updated: HilSensorUpdatedFlags::from_bits_truncate(IMU_FIELDS),
        ..Default::default()
    })
}

/// Whether a frame of the firmware goes on to a ground station attached with `--gcs-udp`: all
/// but `HIL_ACTUATOR_CONTROLS` (#93) and `POSITION_TARGET_LOCAL_NED` (#85), the lockstep answers
/// the simulator consumes. The `hil` build alone sends those two, every tick (100 to 1000 per
/// second); the flight build does not, nor does SIL's pipeline, so a ground station sees the
/// same messages in SIL, in PIL and on the vehicle.
pub fn goes_to_ground_station(m: &MavMessage) -> bool {
    !matches!(
        m,
        MavMessage::HIL_ACTUATOR_CONTROLS(_) | MavMessage::POSITION_TARGET_LOCAL_NED(_)
    )
}

/// The motor commands of one firmware tick, from `HIL_ACTUATOR_CONTROLS` (#93).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Actuators {
    /// The tick time \[µs\] (`time_usec`).
    pub time_us: u64,
    /// Throttle per motor (`controls[0..4]`), mixer order, nominally in [0, 1].
    pub throttle: [f32; 4],
    /// `mode` has `MAV_MODE_FLAG_SAFETY_ARMED`.
    pub armed: bool,
}

impl Actuators {
    /// Reads the message.
    pub fn from_message(m: &HIL_ACTUATOR_CONTROLS_DATA) -> Self {
        Self {
            time_us: m.time_usec,
            throttle: [m.controls[0], m.controls[1], m.controls[2], m.controls[3]],
            armed: m.mode.contains(MavModeFlag::MAV_MODE_FLAG_SAFETY_ARMED),
        }
    }
}

/// The reference of one firmware tick, from `POSITION_TARGET_LOCAL_NED` (#85).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Target {
    /// The tick time \[ms\] (`time_boot_ms`).
    pub time_ms: u32,
    /// Reference position \[m\], NWU (converted from NED).
    pub position: Vector3<f64>,
}

impl Target {
    /// Reads the message.
    pub fn from_message(m: &POSITION_TARGET_LOCAL_NED_DATA) -> Self {
        Self {
            time_ms: m.time_boot_ms,
            position: frames::flip_vector([m.x, m.y, m.z]).cast::<f64>(),
        }
    }
}

/// MAVLink 2 start marker.
const STX: u8 = 0xFD;
/// Marker, header and CRC around the payload.
const OVERHEAD: usize = 12;
/// Signature after the CRC when `incompat_flags & 1`.
const SIGNATURE: usize = 13;

/// Frame counters of a [`FrameReader`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct ReaderCounters {
    /// Frames with a valid CRC whose payload decoded.
    pub valid: u32,
    /// Frames refused: bad CRC, message id not in the common dialect, unknown
    /// incompatibility flags, undecodable payload.
    pub malformed: u32,
    /// Bytes skipped outside frames.
    pub discarded: u64,
}

/// Splits a byte stream (the firmware's serial output) into MAVLink 2 messages of the common
/// dialect. Bytes go in with [`push`](Self::push) in any chunking; [`next_message`](Self::next_message) takes
/// one message at a time, so the caller decides where to stop (lockstep: up to the frame that
/// completes a tick; the rest stays buffered). After a bad frame it looks again from the byte
/// after the bad marker.
#[derive(Clone, Debug, Default)]
pub struct FrameReader {
    buf: Vec<u8>,
    at: usize,
    /// Where the frame [`FrameReader::next_message`] returned last is in `buf` (empty: none
    /// since the last push or call).
    last: std::ops::Range<usize>,
    counters: ReaderCounters,
}

impl FrameReader {
    /// An empty reader.
    pub fn new() -> Self {
        Self::default()
    }

    /// Appends received bytes.
    pub fn push(&mut self, bytes: &[u8]) {
        self.last = 0..0;
        if self.at > 0 && self.at == self.buf.len() {
            self.buf.clear();
            self.at = 0;
        } else if self.at > 4096 {
            self.buf.drain(..self.at);
            self.at = 0;
        }
        self.buf.extend_from_slice(bytes);
    }

    /// Counters so far.
    pub fn counters(&self) -> ReaderCounters {
        self.counters
    }

    /// The bytes held: a partial frame, or frames not taken yet.
    pub fn pending_bytes(&self) -> &[u8] {
        &self.buf[self.at..]
    }

    /// The raw bytes of the frame [`FrameReader::next_message`] returned last (empty after a
    /// [`FrameReader::push`] or a `None`).
    pub fn last_frame(&self) -> &[u8] {
        &self.buf[self.last.clone()]
    }

    /// The next complete message with its header, `None` when more bytes are needed.
    pub fn next_message(&mut self) -> Option<(MavHeader, MavMessage)> {
        self.last = 0..0;
        loop {
            let rest = &self.buf[self.at..];
            let Some(skip) = rest.iter().position(|&b| b == STX) else {
                self.counters.discarded += rest.len() as u64;
                self.at = self.buf.len();
                return None;
            };
            self.counters.discarded += skip as u64;
            self.at += skip;
            let rest = &self.buf[self.at..];
            if rest.len() < 3 {
                return None;
            }
            let incompat = rest[2];
            let len =
                OVERHEAD + usize::from(rest[1]) + if incompat & 1 != 0 { SIGNATURE } else { 0 };
            if incompat & !1 != 0 {
                self.counters.malformed += 1;
                self.at += 1;
                continue;
            }
            if rest.len() < len {
                return None;
            }
            let mut raw = MAVLinkV2MessageRaw::new();
            raw.as_mut_slice()[..len].copy_from_slice(&rest[..len]);
            let parsed = if raw.has_valid_crc::<MavMessage>() {
                MavMessage::parse(MavlinkVersion::V2, raw.message_id(), raw.payload()).ok()
            } else {
                None
            };
            match parsed {
                Some(message) => {
                    self.last = self.at..self.at + len;
                    self.at += len;
                    self.counters.valid += 1;
                    let header = MavHeader {
                        system_id: raw.system_id(),
                        component_id: raw.component_id(),
                        sequence: raw.sequence(),
                    };
                    return Some((header, message));
                }
                None => {
                    self.counters.malformed += 1;
                    self.at += 1;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use firmware::link;
    use firmware::link::mavlink::dialects::common::{HilActuatorControlsFlags, HEARTBEAT_DATA};

    fn frame(m: &MavMessage, sys: u8, seq: u8) -> Vec<u8> {
        let mut buf = [0u8; link::MAX_FRAME];
        let n = link::encode(m, sys, 1, seq, &mut buf);
        buf[..n].to_vec()
    }

    #[test]
    fn hil_sensor_is_frd_and_round_trips() {
        let s = ImuSample {
            gyro_rad_s: [0.1, -0.2, 0.3],
            accel_m_s2: [1.0, 2.0, 9.81],
            time_us: 123_000,
        };
        let bytes = frame(&hil_sensor(&s), 255, 7);
        let mut r = FrameReader::new();
        // Any chunking.
        for chunk in bytes.chunks(5) {
            r.push(chunk);
        }
        let (h, m) = r.next_message().expect("one frame");
        assert_eq!((h.system_id, h.component_id, h.sequence), (255, 1, 7));
        let MavMessage::HIL_SENSOR(d) = m else {
            panic!("{m:?}")
        };
        assert_eq!(d.time_usec, 123_000);
        assert_eq!([d.xacc, d.yacc, d.zacc], [1.0, -2.0, -9.81]);
        assert_eq!([d.xgyro, d.ygyro, d.zgyro], [0.1, 0.2, -0.3]);
        assert_eq!(d.fields_updated.bits(), IMU_FIELDS);
        assert_eq!([d.xmag, d.abs_pressure, d.temperature], [0.0; 3]);
        assert!(r.next_message().is_none());
        assert_eq!(r.counters().valid, 1);
        assert_eq!(r.counters().malformed, 0);
        // The firmware's own decoder (no `hil` feature here) frames it as valid: dropped as
        // unused, not malformed.
        let mut d = link::Decoder::new(1);
        d.push(&bytes, |_| {});
        assert_eq!(d.counters().frames_malformed, 0);
    }

    #[test]
    fn actuator_and_target_frames_parse_through_garbage() {
        let mut controls = [0.0f32; 16];
        controls[..4].copy_from_slice(&[0.1, 0.2, 0.3, 1.0]);
        let act = MavMessage::HIL_ACTUATOR_CONTROLS(HIL_ACTUATOR_CONTROLS_DATA {
            time_usec: 20_000,
            controls,
            mode: MavModeFlag::MAV_MODE_FLAG_SAFETY_ARMED,
            // What the firmware sends: the host reads past the flag.
            flags: HilActuatorControlsFlags::HIL_ACTUATOR_CONTROLS_FLAGS_LOCKSTEP,
        });
        let target = MavMessage::POSITION_TARGET_LOCAL_NED(POSITION_TARGET_LOCAL_NED_DATA {
            time_boot_ms: 20,
            x: 1.0,
            y: 2.0,
            z: -3.0,
            ..Default::default()
        });
        let mut bytes = vec![0x00, 0xFD, 0x42];
        bytes.extend(frame(&act, 1, 0));
        let mut bad = frame(&MavMessage::HEARTBEAT(HEARTBEAT_DATA::default()), 1, 1);
        let k = bad.len() - 1;
        bad[k] ^= 0xFF; // CRC broken
        bytes.extend(bad);
        bytes.extend(frame(&target, 1, 2));
        let mut r = FrameReader::new();
        r.push(&bytes);
        let (_, m) = r.next_message().unwrap();
        // The raw frame, for the telemetry record, without the garbage before it.
        assert_eq!(r.last_frame(), frame(&act, 1, 0));
        let MavMessage::HIL_ACTUATOR_CONTROLS(a) = m else {
            panic!("{m:?}")
        };
        let a = Actuators::from_message(&a);
        assert_eq!(a.time_us, 20_000);
        assert_eq!(a.throttle, [0.1, 0.2, 0.3, 1.0]);
        assert!(a.armed);
        let (_, m) = r.next_message().unwrap();
        // Past the broken frame.
        assert_eq!(r.last_frame(), frame(&target, 1, 2));
        let MavMessage::POSITION_TARGET_LOCAL_NED(t) = m else {
            panic!("{m:?}")
        };
        let t = Target::from_message(&t);
        assert_eq!(t.time_ms, 20);
        assert_eq!(t.position, Vector3::new(1.0, -2.0, 3.0));
        assert!(r.next_message().is_none());
        assert!(r.last_frame().is_empty());
        assert_eq!(r.counters().valid, 2);
        assert!(r.counters().malformed >= 1);
        assert!(r.pending_bytes().is_empty());
        // A partial frame waits for its tail.
        let f = frame(&act, 1, 3);
        r.push(&f[..10]);
        assert!(r.next_message().is_none());
        r.push(&f[10..]);
        assert!(r.next_message().is_some());
    }
}
