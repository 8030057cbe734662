//! The pipeline as a MAVLink peer: acknowledgements to the sender with the right result,
//! message requests and intervals, signing end to end. Given/when/then, on the host.

use crate::link::{self, SIGNATURE};
use crate::pipeline::*;
use mavlink::dialects::common::{
    MavMessage, ATTITUDE_QUATERNION_DATA, COMMAND_ACK_DATA, COMMAND_LONG_DATA, HEARTBEAT_DATA,
    SETUP_SIGNING_DATA,
};
use mavlink::{MavlinkVersion, MessageData};

/// A frame from the ground station (255, 190).
fn gcs_frame(m: &MavMessage) -> Vec<u8> {
    let mut b = [0u8; link::MAX_FRAME];
    let n = link::encode(m, 255, 190, 0, &mut b);
    b[..n].to_vec()
}

fn command(c: MavCmd, p1: f32, p2: f32) -> MavMessage {
    MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
        param1: p1,
        param2: p2,
        command: c,
        target_system: 1,
        target_component: 1,
        ..Default::default()
    })
}

/// (message id, payload, signed) of every frame in `bytes` (whole frames, as telemetry writes).
fn frames(bytes: &[u8]) -> Vec<(u32, Vec<u8>, bool)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        assert_eq!(bytes[i], 0xFD);
        let len = bytes[i + 1] as usize;
        let signed = bytes[i + 2] & 1 != 0;
        let id = u32::from_le_bytes([bytes[i + 7], bytes[i + 8], bytes[i + 9], 0]);
        out.push((id, bytes[i + 10..i + 10 + len].to_vec(), signed));
        i += 12 + len + if signed { SIGNATURE } else { 0 };
    }
    out
}

fn acks(p: &mut FlightPipeline, now_us: u64) -> Vec<link::CommandAck> {
    let mut buf = [0u8; 2048];
    let n = p.telemetry(now_us, &mut buf);
    frames(&buf[..n])
        .into_iter()
        .filter(|f| f.0 == COMMAND_ACK_DATA::ID)
        .map(|f| link::CommandAck::deser(MavlinkVersion::V2, &f.1).unwrap())
        .collect()
}

/// Given a disarmed vehicle, when the ground station sends a command it does not run, one with
/// a bad parameter and a mission start before arming, then each gets one COMMAND_ACK addressed
/// to (255, 190): UNSUPPORTED, DENIED, DENIED.
#[test]
fn every_command_is_acknowledged_to_its_sender() {
    let mut p = FlightPipeline::new(&FlightConfig::built()).unwrap();
    for m in [
        command(MavCmd::MAV_CMD_DO_REPOSITION, 1.0, 4.0),
        command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 2.0, 0.0),
        command(MavCmd::MAV_CMD_MISSION_START, 0.0, 0.0),
    ] {
        p.on_link_bytes(&gcs_frame(&m), 1_000);
    }
    let got: Vec<_> = acks(&mut p, 1_000)
        .iter()
        .map(|a| (a.command, a.result, a.target_system, a.target_component))
        .collect();
    assert_eq!(
        got,
        [
            (
                MavCmd::MAV_CMD_DO_REPOSITION,
                MavResult::MAV_RESULT_UNSUPPORTED,
                255,
                190
            ),
            (
                MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
                MavResult::MAV_RESULT_DENIED,
                255,
                190
            ),
            (
                MavCmd::MAV_CMD_MISSION_START,
                MavResult::MAV_RESULT_DENIED,
                255,
                190
            ),
        ]
    );
}

/// Given a calibrated, converged vehicle whose set-up fails Theorem 2 (a yaw torque limit
/// between Assumption 1's requirement and Theorem 2's bound), when the ground station arms it,
/// then the arm is FAILED (a valid command; the set-up must change before it can succeed), not
/// DENIED or TEMPORARILY_REJECTED, and the vehicle stays disarmed; the same vehicle with the
/// built limit arms (ACCEPTED).
#[test]
#[cfg(not(feature = "uncertified-paper"))] // the default flight file's x500
fn an_arm_on_an_uncertified_set_up_is_failed() {
    let built = FlightConfig::built();
    let boot = FlightPipeline::new(&built)
        .unwrap()
        .boot_report()
        .certificate;
    let rhs_of = |name: &str| boot.conditions.iter().find(|k| k.name == name).unwrap().rhs;
    let tau_z = 0.5 * (rhs_of("assumption1.torque_max_yaw") + rhs_of("theorem2.torque_max_yaw"));
    for (torque_max_yaw, want, state) in [
        (tau_z, MavResult::MAV_RESULT_FAILED, FlightState::Disarmed),
        (
            built.limits.torque_max[2],
            MavResult::MAV_RESULT_ACCEPTED,
            FlightState::Armed,
        ),
    ] {
        let mut c = built;
        c.gyro_calibration_samples = 50;
        c.limits.torque_max[2] = torque_max_yaw;
        let mut p = FlightPipeline::new(&c).unwrap();
        assert_eq!(p.boot_report().gate.is_ok(), state == FlightState::Armed);
        let now = super::fly_ticks(&mut p, 0, 60, true);
        let arm = command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 1.0, 0.0);
        p.on_link_bytes(&gcs_frame(&arm), now);
        let got: Vec<_> = acks(&mut p, now).iter().map(|a| a.result).collect();
        assert_eq!(got, [want], "yaw torque limit {torque_max_yaw}");
        assert_eq!(p.status().state, state);
    }
}

/// Given the default telemetry, when the attitude interval is set to 200 ms, the heartbeat
/// requested and an unknown message requested, then the attitude comes 5 times a second
/// (position still 20), the heartbeat at once instead of a second later, and the unknown
/// request is DENIED.
#[test]
fn message_requests_and_intervals() {
    let mut p = FlightPipeline::new(&FlightConfig::built()).unwrap();
    let mut buf = [0u8; 4096];
    p.telemetry(0, &mut buf);
    p.on_link_bytes(
        &gcs_frame(&command(
            MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL,
            ATTITUDE_QUATERNION_DATA::ID as f32,
            200_000.0,
        )),
        0,
    );
    p.on_link_bytes(
        &gcs_frame(&command(
            MavCmd::MAV_CMD_REQUEST_MESSAGE,
            HEARTBEAT_DATA::ID as f32,
            0.0,
        )),
        0,
    );
    p.on_link_bytes(
        &gcs_frame(&command(MavCmd::MAV_CMD_REQUEST_MESSAGE, 77.0, 0.0)),
        0,
    );
    let mut counts = std::collections::HashMap::new();
    let mut results = Vec::new();
    let mut heartbeats = Vec::new();
    for t in (10_000..=1_000_000).step_by(10_000) {
        let n = p.telemetry(t, &mut buf);
        for (id, payload, _) in frames(&buf[..n]) {
            *counts.entry(id).or_insert(0) += 1;
            if id == HEARTBEAT_DATA::ID {
                heartbeats.push(t);
            }
            if id == COMMAND_ACK_DATA::ID {
                results.push(
                    link::CommandAck::deser(MavlinkVersion::V2, &payload)
                        .unwrap()
                        .result,
                );
            }
        }
    }
    assert_eq!(
        results,
        [
            MavResult::MAV_RESULT_ACCEPTED,
            MavResult::MAV_RESULT_ACCEPTED,
            MavResult::MAV_RESULT_DENIED
        ]
    );
    assert_eq!(counts[&ATTITUDE_QUATERNION_DATA::ID], 5);
    assert_eq!(counts[&LOCAL_POSITION_NED_DATA_ID], 20);
    // The requested heartbeat at once (the periodic one was sent at 0 and is next due at 1 s:
    // a request restarts its period).
    assert_eq!(heartbeats, [10_000]);
}

const LOCAL_POSITION_NED_DATA_ID: u32 = mavlink::dialects::common::LOCAL_POSITION_NED_DATA::ID;

const KEY: [u8; 32] = [0x42; 32];

/// A frame from the ground station, signed with `key` at `timestamp` on link 0.
fn signed_gcs_frame(m: &MavMessage, key: [u8; 32], timestamp: u64) -> Vec<u8> {
    let mut gcs = link::Decoder::with_address(255, 190, None);
    assert!(gcs.install_signing_key(
        link::SigningConfig {
            key,
            link_id: 0,
            accept_unsigned_sensors: true,
        },
        timestamp,
    ));
    let mut b = [0u8; link::MAX_FRAME];
    let n = link::encode(m, 255, 190, 0, &mut b);
    let k = gcs.sign(&mut b, n);
    b[..k].to_vec()
}

/// Given a build with a signing key, when an unsigned arm and one signed with another key
/// arrive, then both are refused and counted with no ACK; a correctly signed disarm is
/// accepted; everything the vehicle sends is signed, and verifies with the key only.
#[test]
fn a_signing_vehicle_acts_only_on_signed_commands_and_signs_its_telemetry() {
    let mut cfg = FlightConfig::built();
    cfg.signing_key = Some(KEY);
    let mut p = FlightPipeline::new(&cfg).unwrap();
    let arm = command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 1.0, 0.0);
    p.on_link_bytes(&gcs_frame(&arm), 1_000);
    p.on_link_bytes(&signed_gcs_frame(&arm, [1; 32], 10), 1_000);
    let c = p.status().counters.link;
    assert_eq!((c.unsigned_refused, c.bad_signature), (1, 1));
    assert!(acks(&mut p, 1_000).is_empty());
    let disarm = command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 0.0, 0.0);
    p.on_link_bytes(&signed_gcs_frame(&disarm, KEY, 20), 2_000);
    let mut buf = [0u8; 2048];
    let n = p.telemetry(2_000, &mut buf);
    let f = frames(&buf[..n]);
    assert!(f.iter().any(|f| f.0 == COMMAND_ACK_DATA::ID));
    assert!(f.iter().all(|f| f.2), "every frame signed");
    // The ground station with the key reads every frame; with another key, none.
    let mut right = link::Decoder::with_address(255, 190, None);
    right.install_signing_key(
        link::SigningConfig {
            key: KEY,
            link_id: 0,
            accept_unsigned_sensors: false,
        },
        0,
    );
    right.push(&buf[..n], |_| {});
    let r = right.counters();
    assert_eq!((r.frames_dropped, r.bad_signature), (f.len() as u32, 0));
    let mut wrong = link::Decoder::with_address(255, 190, None);
    wrong.install_signing_key(
        link::SigningConfig {
            key: [9; 32],
            link_id: 0,
            accept_unsigned_sensors: false,
        },
        0,
    );
    wrong.push(&buf[..n], |_| {});
    assert_eq!(wrong.counters().bad_signature, f.len() as u32);
}

/// `SETUP_SIGNING` for the vehicle (1, 1) installing `key`.
fn setup_signing(key: [u8; 32]) -> MavMessage {
    MavMessage::SETUP_SIGNING(SETUP_SIGNING_DATA {
        initial_timestamp: 1000,
        target_system: 1,
        target_component: 1,
        secret_key: key,
    })
}

/// What one telemetry call sends: the STATUSTEXTs' texts, the acks, and whether every frame
/// is signed (`None`: no frame at all).
fn replies(p: &mut FlightPipeline, now_us: u64) -> (Vec<String>, Vec<MavResult>, Option<bool>) {
    use mavlink::dialects::common::STATUSTEXT_DATA;
    let mut buf = [0u8; 2048];
    let n = p.telemetry(now_us, &mut buf);
    let f = frames(&buf[..n]);
    let texts = f
        .iter()
        .filter(|x| x.0 == STATUSTEXT_DATA::ID)
        .map(|x| {
            let t = STATUSTEXT_DATA::deser(MavlinkVersion::V2, &x.1).unwrap();
            let bytes: Vec<u8> = t.text.iter().copied().take_while(|&b| b != 0).collect();
            String::from_utf8(bytes).unwrap()
        })
        .collect();
    let acks = f
        .iter()
        .filter(|x| x.0 == COMMAND_ACK_DATA::ID)
        .map(|x| {
            link::CommandAck::deser(MavlinkVersion::V2, &x.1)
                .unwrap()
                .result
        })
        .collect();
    let signed = (!f.is_empty()).then(|| f.iter().all(|x| x.2));
    (texts, acks, signed)
}

/// The flight file's build on a wired console (`FIRMWARE_MAVLINK_LINK_TRUST=trusted`).
fn wired() -> FlightConfig {
    FlightConfig {
        link_trust: link::LinkTrust::Trusted,
        ..FlightConfig::built()
    }
}

const NEW_KEY: [u8; 32] = [0x17; 32];

/// Given the default build (an untrusted link: a radio) without a key, when a stranger's
/// unsigned SETUP_SIGNING arrives while disarmed, then it is refused: counted, logged and
/// sent as a STATUSTEXT naming why; no key is installed (the telemetry stays unsigned, a
/// signed frame is still dropped) and the owner's unsigned commands are still answered.
#[test]
fn an_unsigned_setup_signing_on_an_untrusted_link_is_refused_and_installs_no_key() {
    let mut p = FlightPipeline::new(&FlightConfig::built()).unwrap();
    assert_eq!(FlightConfig::built().link_trust, link::LinkTrust::Untrusted);
    p.on_link_bytes(&gcs_frame(&setup_signing(KEY)), 1_000);
    assert_eq!(p.status().counters.refused_commands, 1);
    assert!(
        super::drain_events(&mut p).contains(&Event::CommandRefused {
            command: "setup_signing",
            reason: "unsigned on an untrusted link",
        })
    );
    let (texts, _, signed) = replies(&mut p, 1_000);
    assert_eq!(texts, ["setup_signing: unsigned on an untrusted link"]);
    assert_eq!(signed, Some(false));
    let land = command(MavCmd::MAV_CMD_NAV_LAND, 0.0, 0.0);
    p.on_link_bytes(&signed_gcs_frame(&land, KEY, 3000), 2_000);
    assert_eq!(p.status().counters.link.signed_without_key, 1);
    p.on_link_bytes(&gcs_frame(&land), 3_000);
    assert_eq!(acks(&mut p, 3_000).len(), 1);
}

/// Given a build on a trusted (wired) link without a key, when an unsigned SETUP_SIGNING
/// arrives while disarmed, then signing is on: an unsigned command is refused afterwards, a
/// signed one answered, the telemetry signed. When the key is then lost, an unsigned
/// SETUP_SIGNING over the same cable replaces it: the old key no longer commands, the new one
/// does.
#[test]
fn setup_signing_over_a_trusted_link_sets_and_replaces_the_key() {
    let mut p = FlightPipeline::new(&wired()).unwrap();
    p.on_link_bytes(&gcs_frame(&setup_signing(KEY)), 1_000);
    assert!(
        super::drain_events(&mut p).contains(&Event::CommandAccepted {
            command: "setup_signing"
        })
    );
    let land = command(MavCmd::MAV_CMD_NAV_LAND, 0.0, 0.0);
    p.on_link_bytes(&gcs_frame(&land), 2_000);
    assert_eq!(p.status().counters.link.unsigned_refused, 1);
    p.on_link_bytes(&signed_gcs_frame(&land, KEY, 3000), 3_000);
    let (texts, acks, signed) = replies(&mut p, 3_000);
    assert_eq!((acks.len(), signed), (1, Some(true)), "{texts:?}");
    assert!(
        !texts.iter().any(|t| t.contains("setup_signing")),
        "{texts:?}"
    );
    // The key is lost: the owner plugs in the cable and sets a new one, unsigned.
    super::drain_events(&mut p);
    p.on_link_bytes(&gcs_frame(&setup_signing(NEW_KEY)), 4_000);
    assert!(
        super::drain_events(&mut p).contains(&Event::CommandAccepted {
            command: "setup_signing"
        })
    );
    p.on_link_bytes(&signed_gcs_frame(&land, KEY, 5000), 5_000);
    assert_eq!(p.status().counters.link.bad_signature, 1);
    p.on_link_bytes(&signed_gcs_frame(&land, NEW_KEY, 6000), 6_000);
    assert_eq!(replies(&mut p, 6_000).1.len(), 1);
}

/// Given a build with a key on an untrusted link, when SETUP_SIGNING with a new key arrives
/// signed with the key in force (the owner re-keying) while disarmed, then the new key is in
/// force: frames signed with the old one are dropped as bad signatures, the new one's
/// commands are answered and the telemetry verifies with the new key.
#[test]
fn setup_signing_signed_with_the_current_key_re_keys_an_untrusted_link() {
    let mut cfg = FlightConfig::built();
    cfg.signing_key = Some(KEY);
    let mut p = FlightPipeline::new(&cfg).unwrap();
    p.on_link_bytes(&signed_gcs_frame(&setup_signing(NEW_KEY), KEY, 1000), 1_000);
    assert!(
        super::drain_events(&mut p).contains(&Event::CommandAccepted {
            command: "setup_signing"
        })
    );
    let land = command(MavCmd::MAV_CMD_NAV_LAND, 0.0, 0.0);
    p.on_link_bytes(&signed_gcs_frame(&land, KEY, 2000), 2_000);
    assert_eq!(p.status().counters.link.bad_signature, 1);
    p.on_link_bytes(&signed_gcs_frame(&land, NEW_KEY, 3000), 3_000);
    let mut buf = [0u8; 2048];
    let n = p.telemetry(3_000, &mut buf);
    let f = frames(&buf[..n]);
    assert_eq!(f.iter().filter(|x| x.0 == COMMAND_ACK_DATA::ID).count(), 1);
    let mut owner = link::Decoder::with_address(255, 190, None);
    assert!(owner.install_signing_key(
        link::SigningConfig {
            key: NEW_KEY,
            link_id: 0,
            accept_unsigned_sensors: false,
        },
        0,
    ));
    owner.push(&buf[..n], |_| {});
    let c = owner.counters();
    assert_eq!((c.frames_dropped, c.bad_signature), (f.len() as u32, 0));
}

/// Given a build with a key on an untrusted link, when SETUP_SIGNING arrives signed with
/// another key, then it is dropped as a bad signature (no reply: the vehicle does not answer
/// what it cannot authenticate) and the key in force still commands.
#[test]
fn setup_signing_signed_with_a_wrong_key_is_dropped() {
    let mut cfg = FlightConfig::built();
    cfg.signing_key = Some(KEY);
    let mut p = FlightPipeline::new(&cfg).unwrap();
    p.on_link_bytes(
        &signed_gcs_frame(&setup_signing(NEW_KEY), [0x5a; 32], 1000),
        1_000,
    );
    assert_eq!(p.status().counters.link.bad_signature, 1);
    assert!(!super::drain_events(&mut p).iter().any(|e| matches!(
        e,
        Event::CommandAccepted { .. } | Event::CommandRefused { .. }
    )));
    let land = command(MavCmd::MAV_CMD_NAV_LAND, 0.0, 0.0);
    p.on_link_bytes(&signed_gcs_frame(&land, KEY, 2000), 2_000);
    let (texts, acks, _) = replies(&mut p, 2_000);
    assert_eq!(acks.len(), 1);
    assert!(
        !texts.iter().any(|t| t.contains("setup_signing")),
        "{texts:?}"
    );
}

/// Given an armed vehicle, when SETUP_SIGNING arrives over a trusted link, or signed with the
/// key in force over an untrusted one, then it is refused aloud and the key does not change.
#[test]
fn setup_signing_while_armed_is_refused() {
    let land = command(MavCmd::MAV_CMD_NAV_LAND, 0.0, 0.0);
    // Trusted link, no key: stays without one (its telemetry unsigned).
    let (mut p, now) = super::arm_attempt(wired());
    assert_eq!(p.status().state, crate::safety::FlightState::Armed);
    p.on_link_bytes(&gcs_frame(&setup_signing(KEY)), now);
    let (texts, _, signed) = replies(&mut p, now);
    assert_eq!(texts, ["setup_signing: signing is set up while disarmed"]);
    assert_eq!(signed, Some(false));
    assert_eq!(p.status().counters.refused_commands, 1);
    // Untrusted link with a key: a correctly signed change is refused, the old key still
    // commands. (The arm itself is signed here.)
    let mut cfg = FlightConfig::built();
    cfg.signing_key = Some(KEY);
    cfg.gyro_calibration_samples = 50;
    let mut p = FlightPipeline::new(&cfg).unwrap();
    let now = super::fly_ticks(&mut p, 0, 60, true);
    let arm = command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 1.0, 0.0);
    p.on_link_bytes(&signed_gcs_frame(&arm, KEY, 1000), now);
    assert_eq!(p.status().state, crate::safety::FlightState::Armed);
    replies(&mut p, now);
    p.on_link_bytes(&signed_gcs_frame(&setup_signing(NEW_KEY), KEY, 2000), now);
    let (texts, _, _) = replies(&mut p, now);
    assert_eq!(texts, ["setup_signing: signing is set up while disarmed"]);
    p.on_link_bytes(&signed_gcs_frame(&land, KEY, 3000), now + 1);
    assert_eq!(replies(&mut p, now + 1).1.len(), 1);
}

/// Given a disarmed vehicle during its gyro calibration, when a ground station syncs its clock,
/// asks for the capabilities and the home position, and asks for the helix mode, then: the
/// TIMESYNC answer echoes its ts1 with the vehicle's time in ns; AUTOPILOT_VERSION and
/// HOME_POSITION come once each with their ACKs; SYS_STATUS says the IMU is present but not
/// yet healthy; EXTENDED_SYS_STATE says on the ground; the helix mode is DENIED (not armed).
#[test]
fn status_messages_for_a_ground_station() {
    use mavlink::dialects::common::{
        MavLandedState, MavSysStatusSensor, AUTOPILOT_VERSION_DATA, EXTENDED_SYS_STATE_DATA,
        HOME_POSITION_DATA, SYS_STATUS_DATA, TIMESYNC_DATA,
    };
    let mut p = FlightPipeline::new(&FlightConfig::built()).unwrap();
    let timesync = MavMessage::TIMESYNC(TIMESYNC_DATA {
        tc1: 0,
        ts1: 123_456_789,
    });
    p.on_link_bytes(&gcs_frame(&timesync), 5_000);
    #[allow(deprecated)]
    let capabilities = command(MavCmd::MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES, 1.0, 0.0);
    p.on_link_bytes(&gcs_frame(&capabilities), 5_000);
    let home = command(
        MavCmd::MAV_CMD_REQUEST_MESSAGE,
        HOME_POSITION_DATA::ID as f32,
        0.0,
    );
    p.on_link_bytes(&gcs_frame(&home), 5_000);
    p.on_link_bytes(
        &gcs_frame(&command(MavCmd::MAV_CMD_DO_SET_MODE, 1.0, 4.0)),
        5_000,
    );
    let mut buf = [0u8; 4096];
    let n = p.telemetry(5_000, &mut buf);
    let f = frames(&buf[..n]);
    let one = |id: u32| {
        let v: Vec<_> = f.iter().filter(|x| x.0 == id).collect();
        assert_eq!(v.len(), 1, "message {id}");
        v[0].1.clone()
    };
    let t = TIMESYNC_DATA::deser(MavlinkVersion::V2, &one(TIMESYNC_DATA::ID)).unwrap();
    assert_eq!((t.tc1, t.ts1), (5_000_000, 123_456_789));
    let v = AUTOPILOT_VERSION_DATA::deser(MavlinkVersion::V2, &one(AUTOPILOT_VERSION_DATA::ID))
        .unwrap();
    assert_eq!(v.capabilities, status_messages::CAPABILITIES);
    HOME_POSITION_DATA::deser(MavlinkVersion::V2, &one(HOME_POSITION_DATA::ID)).unwrap();
    let s = SYS_STATUS_DATA::deser(MavlinkVersion::V2, &one(SYS_STATUS_DATA::ID)).unwrap();
    assert!(s
        .onboard_control_sensors_present
        .contains(MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_3D_GYRO));
    assert!(!s
        .onboard_control_sensors_health
        .contains(MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_3D_GYRO));
    let e = EXTENDED_SYS_STATE_DATA::deser(MavlinkVersion::V2, &one(EXTENDED_SYS_STATE_DATA::ID))
        .unwrap();
    assert_eq!(e.landed_state, MavLandedState::MAV_LANDED_STATE_ON_GROUND);
    let results: Vec<_> = f
        .iter()
        .filter(|x| x.0 == COMMAND_ACK_DATA::ID)
        .map(|x| {
            link::CommandAck::deser(MavlinkVersion::V2, &x.1)
                .unwrap()
                .result
        })
        .collect();
    assert_eq!(
        results,
        [
            MavResult::MAV_RESULT_ACCEPTED,
            MavResult::MAV_RESULT_ACCEPTED,
            MavResult::MAV_RESULT_DENIED
        ]
    );
    // On request only: nothing more in the next second.
    let mut again = 0;
    for t in (10_000..=1_000_000).step_by(10_000) {
        let n = p.telemetry(t, &mut buf);
        again += frames(&buf[..n])
            .iter()
            .filter(|x| x.0 == HOME_POSITION_DATA::ID || x.0 == AUTOPILOT_VERSION_DATA::ID)
            .count();
    }
    assert_eq!(again, 0);
}
