//! Unit tests of the script format: the encoder and the reader round-trip, the mission specs
//! become their messages, and truncated inputs parse.

use super::*;
use firmware::link::mavlink::dialects::common::{MavFrame, MavMessage};

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
