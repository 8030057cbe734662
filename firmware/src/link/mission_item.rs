//! One stored mission item: the fields of `MISSION_ITEM_INT` the vehicle keeps, so that a
//! download returns what was uploaded. Local frames carry `x`, `y` in metres × 10⁴ (the
//! message's scaling); `MISSION_ITEM`'s float `x`, `y` are converted to it on arrival.

// MISSION_ITEM, MISSION_REQUEST and MISSION_SET_CURRENT are deprecated in MAVLink's common
// set but still sent by ground stations (MAVProxy's wp module, older QGroundControl).
#![allow(deprecated)]

use mavlink::dialects::common::{MavCmd, MavFrame, MISSION_ITEM_DATA, MISSION_ITEM_INT_DATA};

/// A mission item as uploaded (MAVLink units; NED for the local frames).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MissionItem {
    /// `param1`..`param4` (per command: hold \[s\], acceptance radius \[m\], …, yaw \[deg\]).
    pub params: [f32; 4],
    /// `x`: local frames north \[m × 10⁴\]; global frames latitude \[deg × 10⁷\].
    pub x: i32,
    /// `y`: local frames east \[m × 10⁴\]; global frames longitude \[deg × 10⁷\].
    pub y: i32,
    /// `z`: local frames down \[m\]; global frames altitude \[m\].
    pub z: f32,
    /// `MAV_CMD` id.
    pub command: MavCmd,
    /// `MAV_FRAME` of the position.
    pub frame: MavFrame,
    /// `autocontinue` as sent.
    pub autocontinue: u8,
}

/// `MAV_FRAME`s whose `x`, `y` are latitude and longitude.
pub fn is_global(frame: MavFrame) -> bool {
    use MavFrame::*;
    matches!(
        frame,
        MAV_FRAME_GLOBAL
            | MAV_FRAME_GLOBAL_RELATIVE_ALT
            | MAV_FRAME_GLOBAL_INT
            | MAV_FRAME_GLOBAL_RELATIVE_ALT_INT
            | MAV_FRAME_GLOBAL_TERRAIN_ALT
            | MAV_FRAME_GLOBAL_TERRAIN_ALT_INT
    )
}

impl MissionItem {
    /// From `MISSION_ITEM_INT`, with its sequence number.
    pub fn from_int(m: &MISSION_ITEM_INT_DATA) -> (u16, Self) {
        (
            m.seq,
            Self {
                params: [m.param1, m.param2, m.param3, m.param4],
                x: m.x,
                y: m.y,
                z: m.z,
                command: m.command,
                frame: m.frame,
                autocontinue: m.autocontinue,
            },
        )
    }

    /// From the float `MISSION_ITEM` (deprecated, still sent by some ground stations): `x`, `y`
    /// scaled to the integer message's units (10⁷ for global frames, 10⁴ for local ones),
    /// saturating; NaN becomes `i32::MIN`, which no plan accepts.
    pub fn from_float(m: &MISSION_ITEM_DATA) -> (u16, Self) {
        let scale = if is_global(m.frame) { 1e7 } else { 1e4 };
        let to_int = |v: f32| -> i32 {
            let s = v as f64 * scale;
            if s.is_nan() {
                i32::MIN
            } else {
                libm::round(s).clamp(i32::MIN as f64, i32::MAX as f64) as i32
            }
        };
        (
            m.seq,
            Self {
                params: [m.param1, m.param2, m.param3, m.param4],
                x: to_int(m.x),
                y: to_int(m.y),
                z: m.z,
                command: m.command,
                frame: m.frame,
                autocontinue: m.autocontinue,
            },
        )
    }

    /// As `MISSION_ITEM_INT` number `seq` for (`target_system`, `target_component`).
    pub fn to_int(
        &self,
        seq: u16,
        target_system: u8,
        target_component: u8,
    ) -> MISSION_ITEM_INT_DATA {
        MISSION_ITEM_INT_DATA {
            param1: self.params[0],
            param2: self.params[1],
            param3: self.params[2],
            param4: self.params[3],
            x: self.x,
            y: self.y,
            z: self.z,
            seq,
            command: self.command,
            target_system,
            target_component,
            frame: self.frame,
            current: 0,
            autocontinue: self.autocontinue,
        }
    }

    /// Local position \[m\], NED (`x`, `y` unscaled from 10⁴).
    pub fn local_ned(&self) -> [f32; 3] {
        [self.x as f32 * 1e-4, self.y as f32 * 1e-4, self.z]
    }
}
