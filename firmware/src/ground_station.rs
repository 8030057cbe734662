//! The ground station's side of the link: builders of the MAVLink messages a ground station
//! sends to the vehicle (system 1, component 1), as [`crate::link`] interprets them.
//!
//! - `COMMAND_LONG`: [`arm`] (and the explicit upside-down arm), [`kill`], [`takeoff`],
//!   [`land`], [`mission_start`] (the helix demo);
//! - `SET_POSITION_TARGET_LOCAL_NED`: [`setpoint_nwu`], a hover target given in the
//!   controller's NWU frame and converted to MAVLink's NED by [`crate::frames`];
//! - `PARAM_SET`: [`param_set`].
//!
//! The software-in-the-loop scenarios (host-sim), the processor-in-the-loop runs, the bench
//! fixtures and the tests send these; the vehicle never builds them.

use mavlink::dialects::common::{
    MavCmd, MavFrame, MavMessage, MavParamType, PositionTargetTypemask, COMMAND_LONG_DATA,
    PARAM_SET_DATA, SET_POSITION_TARGET_LOCAL_NED_DATA,
};
use nalgebra::Vector3;

use crate::frames;
use crate::link::{FORCE_ARM_PARAM2, FORCE_DISARM_PARAM2};

/// MAVLink system id of the vehicle the messages are addressed to.
pub const TARGET_SYSTEM: u8 = 1;
/// MAVLink component id of the flight controller the messages are addressed to.
pub const TARGET_COMPONENT: u8 = 1;

/// `COMMAND_LONG` `command` to the vehicle with `param1` = `p1`, `param2` = `p2` and
/// `param7` = `p7` (the other parameters 0).
pub fn command(command: MavCmd, p1: f32, p2: f32, p7: f32) -> MavMessage {
    MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
        param1: p1,
        param2: p2,
        param7: p7,
        command,
        target_system: TARGET_SYSTEM,
        target_component: TARGET_COMPONENT,
        ..Default::default()
    })
}

/// Arm (`MAV_CMD_COMPONENT_ARM_DISARM`, param1 = 1); `inverted` adds the explicit permission to
/// arm upside down (param2 = [`FORCE_ARM_PARAM2`]).
pub fn arm(inverted: bool) -> MavMessage {
    command(
        MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
        1.0,
        if inverted { FORCE_ARM_PARAM2 } else { 0.0 },
        0.0,
    )
}

/// Take off to `height` \[m\] above the arming point (`MAV_CMD_NAV_TAKEOFF`, param7).
pub fn takeoff(height: f32) -> MavMessage {
    command(MavCmd::MAV_CMD_NAV_TAKEOFF, 0.0, 0.0, height)
}

/// Land below the current position (`MAV_CMD_NAV_LAND`).
pub fn land() -> MavMessage {
    command(MavCmd::MAV_CMD_NAV_LAND, 0.0, 0.0, 0.0)
}

/// Start the helix demo mission (`MAV_CMD_MISSION_START`).
pub fn mission_start() -> MavMessage {
    command(MavCmd::MAV_CMD_MISSION_START, 0.0, 0.0, 0.0)
}

/// Kill: stop the motors wherever the vehicle is (`MAV_CMD_COMPONENT_ARM_DISARM`, param1 = 0,
/// param2 = [`FORCE_DISARM_PARAM2`]).
pub fn kill() -> MavMessage {
    command(
        MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
        0.0,
        FORCE_DISARM_PARAM2,
        0.0,
    )
}

/// Hover target `position` \[m\] and `yaw` \[rad\], both in the controller's NWU frame, sent as
/// `SET_POSITION_TARGET_LOCAL_NED` in `MAV_FRAME_LOCAL_NED` (position and yaw used; velocity,
/// acceleration and yaw rate ignored).
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
        target_system: TARGET_SYSTEM,
        target_component: TARGET_COMPONENT,
        coordinate_frame: MavFrame::MAV_FRAME_LOCAL_NED,
        ..Default::default()
    })
}

/// `PARAM_SET` of parameter `name` (at most 16 characters, [`crate::params`]) to `value`, typed
/// `MAV_PARAM_TYPE_REAL32` as every parameter of the table.
pub fn param_set(name: &str, value: f32) -> MavMessage {
    MavMessage::PARAM_SET(PARAM_SET_DATA {
        param_value: value,
        target_system: TARGET_SYSTEM,
        target_component: TARGET_COMPONENT,
        param_id: name.into(),
        param_type: MavParamType::MAV_PARAM_TYPE_REAL32,
    })
}

/// `MISSION_COUNT`: an upload of `count` mission items follows (`MAV_MISSION_TYPE_MISSION`).
pub fn mission_count(count: u16) -> MavMessage {
    MavMessage::MISSION_COUNT(mavlink::dialects::common::MISSION_COUNT_DATA {
        count,
        target_system: TARGET_SYSTEM,
        target_component: TARGET_COMPONENT,
    })
}

/// `MISSION_ITEM_INT` number `seq` in `MAV_FRAME_LOCAL_NED`: `command` at `ned` (north, east,
/// down \[m\]) with param1 `hold` \[s\], param2 `radius` \[m\] and param4 `yaw_deg` \[deg, NED\].
pub fn mission_item_local(
    seq: u16,
    command: MavCmd,
    ned: [f32; 3],
    hold: f32,
    radius: f32,
    yaw_deg: f32,
) -> MavMessage {
    MavMessage::MISSION_ITEM_INT(mavlink::dialects::common::MISSION_ITEM_INT_DATA {
        param1: hold,
        param2: radius,
        param3: 0.0,
        param4: yaw_deg,
        x: libm::roundf(ned[0] * 1e4) as i32,
        y: libm::roundf(ned[1] * 1e4) as i32,
        z: ned[2],
        seq,
        command,
        target_system: TARGET_SYSTEM,
        target_component: TARGET_COMPONENT,
        frame: MavFrame::MAV_FRAME_LOCAL_NED,
        current: 0,
        autocontinue: 1,
    })
}

/// `MISSION_REQUEST_LIST` (the mission, type 0).
pub fn mission_request_list() -> MavMessage {
    MavMessage::MISSION_REQUEST_LIST(mavlink::dialects::common::MISSION_REQUEST_LIST_DATA {
        target_system: TARGET_SYSTEM,
        target_component: TARGET_COMPONENT,
    })
}

/// `MISSION_REQUEST_INT` for item `seq`.
pub fn mission_request(seq: u16) -> MavMessage {
    MavMessage::MISSION_REQUEST_INT(mavlink::dialects::common::MISSION_REQUEST_INT_DATA {
        seq,
        target_system: TARGET_SYSTEM,
        target_component: TARGET_COMPONENT,
    })
}

/// `MISSION_CLEAR_ALL` (the mission, type 0).
pub fn mission_clear_all() -> MavMessage {
    MavMessage::MISSION_CLEAR_ALL(mavlink::dialects::common::MISSION_CLEAR_ALL_DATA {
        target_system: TARGET_SYSTEM,
        target_component: TARGET_COMPONENT,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::link::{Command, Decoder, Inbound};

    /// Every builder is read back by the vehicle's decoder as the command it names.
    #[test]
    fn vehicle_reads_what_the_ground_station_sends() {
        let cases = [
            (arm(false), Command::Arm { inverted: false }),
            (arm(true), Command::Arm { inverted: true }),
            (kill(), Command::Kill),
            (takeoff(1.5), Command::Takeoff { height: Some(1.5) }),
            (land(), Command::Land),
            (mission_start(), Command::StartHelix),
        ];
        for (message, expected) in cases {
            let mut buf = [0u8; crate::link::MAX_FRAME];
            let n = crate::link::encode(&message, 255, 190, 0, &mut buf);
            let mut decoder = Decoder::new(TARGET_SYSTEM);
            let mut got = None;
            decoder.push(&buf[..n], |i| got = Some(i));
            match got {
                Some(Inbound::Command { command, .. }) => assert_eq!(command, expected),
                other => panic!("{expected:?} read back as {other:?}"),
            }
        }
        let mut buf = [0u8; crate::link::MAX_FRAME];
        let message = setpoint_nwu(Vector3::new(1.0, 0.5, 1.2), 1.0);
        let n = crate::link::encode(&message, 255, 190, 0, &mut buf);
        let mut decoder = Decoder::new(TARGET_SYSTEM);
        let mut got = None;
        decoder.push(&buf[..n], |i| got = Some(i));
        match got {
            Some(Inbound::Setpoint { position, yaw }) => {
                assert_eq!(position, Vector3::new(1.0, 0.5, 1.2));
                assert_eq!(yaw, Some(1.0));
            }
            other => panic!("setpoint read back as {other:?}"),
        }
    }
}
