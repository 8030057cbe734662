//! The MAVLink messages of the frame specs: [`message`] builds a [`FrameSpec`]'s message
//! at the script's clock, [`frame_bytes`] its CRC-valid frame as the ground station sends it.

use firmware::link;
use firmware::link::mavlink::dialects::common::{
    HilSensorUpdatedFlags, MavFrame, MavMessage, PositionTargetTypemask, ATT_POS_MOCAP_DATA,
    COMMAND_LONG_DATA, HIL_SENSOR_DATA, MISSION_ACK_DATA, MISSION_CLEAR_ALL_DATA,
    MISSION_COUNT_DATA, MISSION_ITEM_INT_DATA, MISSION_REQUEST_INT_DATA, MISSION_REQUEST_LIST_DATA,
    ODOMETRY_DATA, SET_POSITION_TARGET_LOCAL_NED_DATA,
};

use super::{FrameSpec, MissionSpec, COMMANDS, MISSION_COMMANDS, MISSION_RESULTS};

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
