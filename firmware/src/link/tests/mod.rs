//! Decoder, interpretation, addressing and signing tests.

mod signing;

use super::*;
use mavlink::dialects::common::{
    MavCmd, MavFrame, MavMessage, PositionTargetTypemask, ATT_POS_MOCAP_DATA, COMMAND_INT_DATA,
    COMMAND_LONG_DATA, HEARTBEAT_DATA, SET_POSITION_TARGET_LOCAL_NED_DATA,
    VISION_POSITION_ESTIMATE_DATA,
};

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

/// Given a cut-off frame whose length byte claims more than what follows (a marker, a long
/// length, no flags), when a kill and then nothing else arrive, then the kill is handled at its
/// own last byte, in any chunking, and the cut-off frame is counted malformed; the same with a
/// pose frame behind the kill, which also gets through.
#[test]
fn a_cut_off_frame_does_not_hold_back_the_frames_behind_it() {
    let kill = MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
        param2: FORCE_DISARM_PARAM2,
        command: MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
        target_system: 1,
        ..Default::default()
    });
    let (k, kn) = frame(&kill, 0);
    let (p, pn) = frame(&mocap(1.0), 1);
    for claimed in [kn as u8, 36, 200, 255] {
        let mut stream = vec![STX, claimed, 0];
        stream.extend_from_slice(&k[..kn]);
        for chunk in [1usize, 2, 5, 64, 280] {
            let mut d = Decoder::new(1);
            let mut got = Vec::new();
            for c in stream.chunks(chunk) {
                got.extend(collect(&mut d, c));
            }
            assert_eq!(got.len(), 1, "claimed {claimed}, chunk {chunk}");
            assert!(matches!(
                got[0],
                Inbound::Command {
                    command: Command::Kill,
                    ..
                }
            ));
            assert!(d.holds_nothing(), "claimed {claimed}, chunk {chunk}");
            assert_eq!(d.counters().frames_malformed, 1);
            assert_eq!(d.counters().frames_ok, 1);
            let behind = collect(&mut d, &p[..pn]);
            assert_eq!(behind.len(), 1);
        }
    }
}

/// Given a good frame whose payload holds a marker byte (a false frame start inside it), when
/// it arrives, then it is accepted whole: only a checked frame ends a held-back one early.
#[test]
fn a_marker_inside_a_payload_is_not_a_frame() {
    // 0xFD inside `x`'s bytes: f32::from_le_bytes([0, 0, 0xFD, 0x3F]).
    let x = f32::from_le_bytes([0, 0, STX, 0x3F]);
    let (f, n) = frame(&mocap(x), 0);
    assert!(f[1..n].contains(&STX));
    for chunk in [1usize, 3, 280] {
        let mut d = Decoder::new(1);
        let mut got = Vec::new();
        for c in f[..n].chunks(chunk) {
            got.extend(collect(&mut d, c));
        }
        assert_eq!(got.len(), 1, "chunk {chunk}");
        assert_eq!(d.counters().frames_malformed, 0);
    }
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
    /// any mix of valid frames, frames with one corrupted byte (length bytes included),
    /// cut-off frames and junk, in any chunking.
    #[test]
    fn feed_equals_byte_by_byte(
        pieces in proptest::collection::vec(
            (0u8..4, -1e3f32..1e3, proptest::collection::vec(proptest::prelude::any::<u8>(), 0..40),
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
                // A cut-off frame: a marker and a length, held back until a frame behind
                // it checks or its own length is in.
                2 => stream.extend_from_slice(&[STX, flip, 0]),
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
        proptest::prop_assert_eq!(fed.pending(), bytewise.pending());
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

fn command_long(command: MavCmd, p1: f32, system: u8, component: u8) -> MavMessage {
    MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
        param1: p1,
        command,
        target_system: system,
        target_component: component,
        ..Default::default()
    })
}

/// Given a vehicle (1, 1), when commands are addressed to components 0, 1 and 99, then the
/// broadcast and its own are used and the other is dropped (counted), for COMMAND_LONG and a
/// setpoint alike.
#[test]
fn target_component_is_respected() {
    use MavCmd::MAV_CMD_COMPONENT_ARM_DISARM as ARM;
    for (component, used) in [(0u8, true), (1, true), (99, false)] {
        let mut d = Decoder::new(1);
        let (f, n) = frame(&command_long(ARM, 1.0, 1, component), 0);
        assert_eq!(
            collect(&mut d, &f[..n]).len(),
            usize::from(used),
            "{component}"
        );
        let sp = MavMessage::SET_POSITION_TARGET_LOCAL_NED(SET_POSITION_TARGET_LOCAL_NED_DATA {
            target_system: 1,
            target_component: component,
            coordinate_frame: MavFrame::MAV_FRAME_LOCAL_NED,
            type_mask: PositionTargetTypemask::empty(),
            ..Default::default()
        });
        let (f, n) = frame(&sp, 1);
        assert_eq!(
            collect(&mut d, &f[..n]).len(),
            usize::from(used),
            "{component}"
        );
        assert_eq!(d.counters().frames_dropped, if used { 0 } else { 2 });
    }
}

/// Every command addressed to the vehicle yields something to acknowledge, with the sender's
/// ids: unknown ones are Unsupported, an arm with param1 = 2 a bad parameter; COMMAND_INT
/// runs the same commands as COMMAND_LONG.
#[test]
fn every_command_is_answerable_with_its_sender() {
    let sender = Sender {
        system: 200,
        component: 1,
    };
    let cases = [
        (
            command_long(MavCmd::MAV_CMD_DO_REPOSITION, 1.0, 1, 1),
            Err(CommandFault::Unsupported),
        ),
        (
            MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
                param1: 1.0,
                param2: 4.0,
                command: MavCmd::MAV_CMD_DO_SET_MODE,
                target_system: 1,
                ..Default::default()
            }),
            Ok(Command::SetMode { custom_mode: 4 }),
        ),
        (
            // Base mode without MAV_MODE_FLAG_CUSTOM_MODE_ENABLED.
            command_long(MavCmd::MAV_CMD_DO_SET_MODE, 0.0, 1, 1),
            Err(CommandFault::BadParameter),
        ),
        (
            command_long(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 2.0, 1, 1),
            Err(CommandFault::BadParameter),
        ),
        (
            command_long(MavCmd::MAV_CMD_REQUEST_MESSAGE, 30.5, 0, 0),
            Err(CommandFault::BadParameter),
        ),
        (
            command_long(MavCmd::MAV_CMD_REQUEST_MESSAGE, 31.0, 0, 0),
            Ok(Command::RequestMessage { id: 31 }),
        ),
        (
            MavMessage::COMMAND_INT(COMMAND_INT_DATA {
                param1: 1.0,
                command: MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
                target_system: 1,
                target_component: 1,
                ..Default::default()
            }),
            Ok(Command::Arm { inverted: false }),
        ),
        (
            MavMessage::COMMAND_INT(COMMAND_INT_DATA {
                z: 2.5,
                command: MavCmd::MAV_CMD_NAV_TAKEOFF,
                target_system: 1,
                ..Default::default()
            }),
            Ok(Command::Takeoff { height: Some(2.5) }),
        ),
        (
            MavMessage::COMMAND_INT(COMMAND_INT_DATA {
                command: MavCmd::MAV_CMD_DO_REPOSITION,
                target_system: 1,
                ..Default::default()
            }),
            Err(CommandFault::Unsupported),
        ),
    ];
    for (m, want) in cases {
        let (f, n) = frame(&m, 0);
        let got = collect(&mut Decoder::new(1), &f[..n]);
        assert_eq!(got.len(), 1, "{m:?}");
        match (got[0], want) {
            (
                Inbound::Command {
                    command, sender: s, ..
                },
                Ok(c),
            ) => assert_eq!((command, s), (c, sender)),
            (
                Inbound::CommandFault {
                    fault, sender: s, ..
                },
                Err(w),
            ) => assert_eq!((fault, s), (w, sender)),
            (g, w) => panic!("{g:?} vs {w:?}"),
        }
    }
}

/// VISION_POSITION_ESTIMATE (NED, Euler angles) is a pose: yaw 90° east in NED is a quarter
/// turn clockwise seen from above, −90° about z up in NWU.
#[test]
fn vision_position_estimate_is_a_pose() {
    let m = MavMessage::VISION_POSITION_ESTIMATE(VISION_POSITION_ESTIMATE_DATA {
        x: 1.0,
        y: 2.0,
        z: -3.0,
        yaw: core::f32::consts::FRAC_PI_2,
        ..Default::default()
    });
    let (f, n) = frame(&m, 0);
    match collect(&mut Decoder::new(1), &f[..n])[..] {
        [Inbound::Pose {
            position,
            attitude,
            source: PoseSource::Vision,
        }] => {
            assert_eq!(position, Vector3::new(1.0, -2.0, 3.0));
            let q = nalgebra::UnitQuaternion::from_quaternion(attitude);
            let (_, _, yaw) = q.euler_angles();
            assert!((yaw + core::f32::consts::FRAC_PI_2).abs() < 1e-5, "{yaw}");
        }
        ref other => panic!("{other:?}"),
    }
}

/// The decoder's inline CRC-extra constants for the pose messages are the dialect's.
#[test]
fn pose_crc_extras_are_the_dialects() {
    use mavlink::dialects::common::{ATT_POS_MOCAP_DATA, ODOMETRY_DATA};
    use mavlink::{Message, MessageData};
    for (id, extra) in [
        (ATT_POS_MOCAP_DATA::ID, ATT_POS_MOCAP_DATA::EXTRA_CRC),
        (ODOMETRY_DATA::ID, ODOMETRY_DATA::EXTRA_CRC),
    ] {
        assert_eq!(MavMessage::extra_crc(id), extra);
    }
}

/// The mission messages did not make `Inbound` larger than a pose needs moved per frame: at
/// most 48 bytes (the size the decoder's hot path was measured with).
#[test]
fn inbound_stays_small() {
    assert!(
        core::mem::size_of::<Inbound>() <= 48,
        "{}",
        core::mem::size_of::<Inbound>()
    );
}
