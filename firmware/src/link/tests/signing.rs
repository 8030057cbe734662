//! Signing: frames dropped without a key, only fresh correct signatures command, stale
//! streams, interoperability with the mavlink crate, and who may set up or change the key with
//! SETUP_SIGNING (the link's trust, the frame's signature).

use super::*;
use crate::link::*;
use mavlink::dialects::common::{MavCmd, MavMessage, HEARTBEAT_DATA, SETUP_SIGNING_DATA};

const KEY: [u8; 32] = [7; 32];

fn signing(accept_unsigned_sensors: bool) -> Option<SigningConfig> {
    Some(SigningConfig {
        key: KEY,
        link_id: 0,
        accept_unsigned_sensors,
    })
}

/// A frame signed by the mavlink crate's own implementation (independent of ours), from
/// system 200, with `key` and the wall-clock signing timestamp it uses.
fn signed_by_mavlink(m: &MavMessage, key: [u8; 32], link_id: u8) -> Vec<u8> {
    use mavlink_core::{MAVLinkV2MessageRaw, MavHeader, SigningConfig, SigningData};
    let mut raw = MAVLinkV2MessageRaw::new();
    raw.serialize_message_for_signing(
        MavHeader {
            system_id: 200,
            component_id: 1,
            sequence: 0,
        },
        m,
    );
    SigningData::from_config(SigningConfig::new(key, link_id, true, false)).sign_message(&mut raw);
    raw.raw_bytes().to_vec()
}

/// Without a key, a signed frame is dropped and counted (MAVLink 2: a system that does not
/// check signatures must not act on signed frames): the arm signed with a random key that was
/// once accepted.
#[test]
fn without_a_key_signed_frames_are_dropped() {
    let arm = command_long(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 1.0, 1, 1);
    let f = signed_by_mavlink(&arm, [0x5a; 32], 0);
    let mut d = Decoder::new(1);
    assert!(collect(&mut d, &f).is_empty());
    assert_eq!(d.counters().signed_without_key, 1);
    assert_eq!(d.counters().frames_ok, 0);
}

/// With a key: a correctly signed arm is used; the same frame again (a replay), one signed
/// with another key, and an unsigned one are each refused and counted; an unsigned pose is
/// used or refused as the set-up says.
#[test]
fn with_a_key_only_fresh_correct_signatures_command() {
    let arm = command_long(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 1.0, 1, 1);
    let good = signed_by_mavlink(&arm, KEY, 0);
    let mut d = Decoder::with_address(1, 1, signing(true));
    assert!(matches!(
        collect(&mut d, &good)[..],
        [Inbound::Command {
            command: Command::Arm { .. },
            ..
        }]
    ));
    assert!(collect(&mut d, &good).is_empty());
    assert_eq!(d.counters().stale_signature, 1);
    let forged = signed_by_mavlink(&arm, [8; 32], 0);
    assert!(collect(&mut d, &forged).is_empty());
    assert_eq!(d.counters().bad_signature, 1);
    let (f, n) = frame(&arm, 3);
    assert!(collect(&mut d, &f[..n]).is_empty());
    assert_eq!(d.counters().unsigned_refused, 1);
    // Unsigned poses: as the set-up says.
    let (pose, n) = frame(&mocap(1.0), 4);
    assert_eq!(collect(&mut d, &pose[..n]).len(), 1);
    let mut strict = Decoder::with_address(1, 1, signing(false));
    assert!(collect(&mut strict, &pose[..n]).is_empty());
    assert_eq!(strict.counters().unsigned_refused, 1);
    assert_eq!(d.counters().frames_ok, 2);
}

/// A new stream more than a minute behind the vehicle's signing clock is a replay too.
#[test]
fn a_new_stream_far_behind_the_clock_is_stale() {
    let mut d = Decoder::with_address(1, 1, signing(true));
    // Another stream (link 1) moves the vehicle's clock to now.
    let now = signed_by_mavlink(&mocap(0.0), KEY, 1);
    assert_eq!(collect(&mut d, &now).len(), 1);
    // A frame from link 2 signed by us with the clock two minutes earlier.
    let mut old = Decoder::with_address(200, 1, signing(true));
    old.install_signing_key(
        SigningConfig {
            ..signing(true).unwrap()
        },
        0,
    );
    let (mut f, n) = frame(&mocap(0.0), 0);
    let stamp = u64::from_le_bytes({
        let mut t = [0u8; 8];
        t[..6].copy_from_slice(&now[now.len() - 12..now.len() - 6]);
        t
    }) - 2 * 60 * 100_000;
    let mut s = Decoder::with_address(200, 1, None);
    assert!(s.install_signing_key(
        SigningConfig {
            link_id: 2,
            ..signing(true).unwrap()
        },
        stamp,
    ));
    let k = s.sign(&mut f, n);
    assert_eq!(k, n + SIGNATURE);
    assert!(collect(&mut d, &f[..k]).is_empty());
    assert_eq!(d.counters().stale_signature, 1);
}

/// What the vehicle signs, the mavlink crate's implementation verifies: same frame bytes
/// (flag, CRC), same signature; and its timestamps follow the ground station's.
#[test]
fn our_signatures_verify_with_the_mavlink_crate() {
    use mavlink_core::{MAVLinkV2MessageRaw, MavHeader, SigningConfig as Cfg, SigningData};
    let mut vehicle = Decoder::with_address(1, 1, signing(true));
    // The ground station's heartbeat sets the vehicle's signing clock.
    let hb = signed_by_mavlink(&MavMessage::HEARTBEAT(HEARTBEAT_DATA::default()), KEY, 0);
    collect(&mut vehicle, &hb);
    assert_eq!(
        vehicle.counters().frames_dropped,
        1,
        "{:?}",
        vehicle.counters()
    );
    let gcs = SigningData::from_config(Cfg::new(KEY, 0, false, false));
    for seq in 0..3u8 {
        let m = mocap(f32::from(seq));
        let mut out = [0u8; MAX_FRAME];
        let n = encode(&m, 1, 1, seq, &mut out);
        let k = vehicle.sign(&mut out, n);
        assert_eq!(k, n + SIGNATURE);
        let mut raw = MAVLinkV2MessageRaw::new();
        raw.serialize_message_for_signing(
            MavHeader {
                system_id: 1,
                component_id: 1,
                sequence: seq,
            },
            &m,
        );
        *raw.signature_link_id_mut() = out[n];
        raw.signature_timestamp_bytes_mut()
            .copy_from_slice(&out[n + 1..n + 7]);
        raw.signature_value_mut().copy_from_slice(&out[n + 7..k]);
        assert_eq!(raw.raw_bytes(), &out[..k]);
        assert!(gcs.verify_signature(&raw), "frame {seq}");
    }
}

/// `SETUP_SIGNING` for the vehicle (1, 1) with `key` and an initial timestamp of 5.
fn setup(key: [u8; 32]) -> MavMessage {
    MavMessage::SETUP_SIGNING(SETUP_SIGNING_DATA {
        initial_timestamp: 5,
        target_system: 1,
        target_component: 1,
        secret_key: key,
    })
}

/// `m` from system 200 signed by our signer with `key` on link 0, its signing timestamp
/// `timestamp` \[10 µs since 2015-01-01\].
fn signed_at(m: &MavMessage, key: [u8; 32], timestamp: u64) -> Vec<u8> {
    let mut s = Decoder::with_address(200, 1, None);
    assert!(s.install_signing_key(
        SigningConfig {
            key,
            ..signing(true).unwrap()
        },
        timestamp - 1,
    ));
    let (mut f, n) = frame(m, 0);
    let k = s.sign(&mut f, n);
    assert_eq!(k, n + SIGNATURE);
    f[..k].to_vec()
}

/// The authority the decoder gives the one `SETUP_SIGNING` in `bytes`, or `None` when it
/// passed none on.
fn authority(d: &mut Decoder, bytes: &[u8]) -> Option<SetupAuthority> {
    match collect(d, bytes)[..] {
        [Inbound::SetupSigning {
            key: _,
            initial_timestamp: 5,
            authority,
            ..
        }] => Some(authority),
        [] => None,
        ref other => panic!("not one SETUP_SIGNING: {other:?}"),
    }
}

/// Given a link without a key, when an unsigned SETUP_SIGNING arrives, then on an untrusted
/// link (a radio: the default) it is passed on as unauthenticated, for the pipeline to refuse,
/// and on a trusted one (a wired console) as the trusted link's; a signed one is dropped on
/// both (no key to check it with).
#[test]
fn without_a_key_only_a_trusted_link_may_set_one_up() {
    let (f, n) = frame(&setup(KEY), 0);
    let mut radio = Decoder::new(1);
    assert_eq!(radio.trust(), LinkTrust::Untrusted);
    assert_eq!(
        authority(&mut radio, &f[..n]),
        Some(SetupAuthority::Unauthenticated)
    );
    let mut wired = Decoder::new(1).with_trust(LinkTrust::Trusted);
    assert_eq!(
        authority(&mut wired, &f[..n]),
        Some(SetupAuthority::TrustedLink)
    );
    let signed = signed_at(&setup(KEY), KEY, 1000);
    for mut d in [radio, wired] {
        assert_eq!(authority(&mut d, &signed), None);
        assert_eq!(d.counters().signed_without_key, 1);
    }
}

/// Given an untrusted link with a key, when SETUP_SIGNING arrives signed with that key, then it
/// is passed on as the owner's re-keying; signed with another key, it is dropped as a bad
/// signature; unsigned, it is refused like any unsigned command; the same signed frame again
/// (a replay) is stale.
#[test]
fn with_a_key_an_untrusted_link_takes_setup_signed_with_it_only() {
    let mut d = Decoder::with_address(1, 1, signing(true));
    let signed = signed_at(&setup([9; 32]), KEY, 1000);
    assert_eq!(
        authority(&mut d, &signed),
        Some(SetupAuthority::SignedWithCurrentKey)
    );
    assert_eq!(authority(&mut d, &signed), None);
    assert_eq!(d.counters().stale_signature, 1);
    assert_eq!(
        authority(&mut d, &signed_at(&setup([9; 32]), [8; 32], 2000)),
        None
    );
    assert_eq!(d.counters().bad_signature, 1);
    let (f, n) = frame(&setup([9; 32]), 1);
    assert_eq!(authority(&mut d, &f[..n]), None);
    assert_eq!(d.counters().unsigned_refused, 1);
    assert_eq!(d.counters().frames_ok, 1);
}

/// Given a trusted (wired) link with a key, when an unsigned SETUP_SIGNING arrives, then it is
/// passed on as the trusted link's (the way to replace a lost key); an unsigned arm on the
/// same link is still refused: trust opens nothing but the key.
#[test]
fn a_trusted_link_replaces_a_key_unsigned_and_nothing_else() {
    let mut d = Decoder::with_address(1, 1, signing(true)).with_trust(LinkTrust::Trusted);
    let (f, n) = frame(&setup([9; 32]), 0);
    assert_eq!(
        authority(&mut d, &f[..n]),
        Some(SetupAuthority::TrustedLink)
    );
    let arm = command_long(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 1.0, 1, 1);
    let (f, n) = frame(&arm, 1);
    assert!(collect(&mut d, &f[..n]).is_empty());
    assert_eq!(d.counters().unsigned_refused, 1);
    // A wrong signature is not waved through either.
    assert_eq!(
        authority(&mut d, &signed_at(&setup([9; 32]), [8; 32], 2000)),
        None
    );
    assert_eq!(d.counters().bad_signature, 1);
}

/// Given a key in force, when another is installed, then frames signed with the old key are
/// bad signatures and the new key's are used; when the old key comes back, a frame it signed
/// before is still a replay (the streams' timestamps survive a change of key). The all-zero
/// key is refused, changing nothing.
#[test]
fn a_new_key_replaces_the_old_and_replays_stay_stale() {
    const NEW: [u8; 32] = [9; 32];
    let pose = mocap(0.0);
    let mut d = Decoder::with_address(1, 1, signing(false));
    let old_frame = signed_at(&pose, KEY, 1000);
    assert_eq!(collect(&mut d, &old_frame).len(), 1);
    assert!(d.install_signing_key(
        SigningConfig {
            key: NEW,
            ..signing(false).unwrap()
        },
        5
    ));
    assert!(collect(&mut d, &signed_at(&pose, KEY, 2000)).is_empty());
    assert_eq!(d.counters().bad_signature, 1);
    assert_eq!(collect(&mut d, &signed_at(&pose, NEW, 3000)).len(), 1);
    assert!(!d.install_signing_key(
        SigningConfig {
            key: [0; 32],
            ..signing(false).unwrap()
        },
        0
    ));
    assert_eq!(collect(&mut d, &signed_at(&pose, NEW, 4000)).len(), 1);
    assert!(d.install_signing_key(signing(false).unwrap(), 5));
    assert!(collect(&mut d, &old_frame).is_empty());
    assert_eq!(d.counters().stale_signature, 1);
    assert_eq!(collect(&mut d, &signed_at(&pose, KEY, 5000)).len(), 1);
}
