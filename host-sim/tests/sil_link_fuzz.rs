//! SIL scenario 4: malformed, truncated and random byte streams into the MAVLink link: no
//! panic, frames counted as dropped or malformed, valid frames around them still decoded.

use firmware::config::FlightConfig;
use firmware::link::mavlink::dialects::common::{MavMessage, ATT_POS_MOCAP_DATA, HEARTBEAT_DATA};
use firmware::link::{self, Decoder, Inbound, MAX_FRAME};
use firmware::pipeline::FlightPipeline;
use firmware::safety::FlightState;
use proptest::prelude::*;

fn frame(m: &MavMessage, seq: u8) -> Vec<u8> {
    let mut b = [0u8; MAX_FRAME];
    let n = link::encode(m, 255, 190, seq, &mut b);
    b[..n].to_vec()
}

fn mocap(x: f32) -> Vec<u8> {
    frame(
        &MavMessage::ATT_POS_MOCAP(ATT_POS_MOCAP_DATA {
            time_usec: 1,
            q: [1.0, 0.0, 0.0, 0.0],
            x,
            y: 0.0,
            z: -1.0,
        }),
        0,
    )
}

fn push_chunked(d: &mut Decoder, bytes: &[u8], chunks: &[usize]) -> usize {
    push_chunked_collect(d, bytes, chunks).len()
}

/// Pushes `bytes` in the given chunk sizes (cycled) and returns every accepted message.
fn push_chunked_collect(d: &mut Decoder, bytes: &[u8], chunks: &[usize]) -> Vec<Inbound> {
    let mut got = Vec::new();
    let mut i = 0;
    let mut k = 0;
    while i < bytes.len() {
        let n = chunks
            .get(k % chunks.len().max(1))
            .copied()
            .unwrap_or(7)
            .max(1);
        let j = (i + n).min(bytes.len());
        d.push(&bytes[i..j], |m| got.push(m));
        i = j;
        k += 1;
    }
    got
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Random bytes: no panic, nothing accepted that is not a valid frame, the pipeline stays
    /// disarmed with its motors at zero.
    #[test]
    fn random_bytes(bytes in prop::collection::vec(any::<u8>(), 0..4000),
                    chunks in prop::collection::vec(1usize..300, 1..10)) {
        let mut d = Decoder::new(1);
        push_chunked(&mut d, &bytes, &chunks);
        let c = d.counters();
        prop_assert!(c.bytes_discarded as usize <= bytes.len());
        let mut p = FlightPipeline::new(&FlightConfig::built()).unwrap();
        for (k, c) in bytes.chunks(chunks[0]).enumerate() {
            p.on_link_bytes(c, k as u64 * 1000);
        }
        let out = p.control_tick(10_000);
        prop_assert_eq!(out.throttle, [0.0; 4]);
        prop_assert_eq!(p.status().state, FlightState::Disarmed);
    }

    /// Valid frames, some truncated, some with a flipped byte, garbage between: every intact
    /// frame is decoded, every damaged one is counted, none is accepted.
    #[test]
    fn damaged_frames_are_counted(plan in prop::collection::vec((0u8..4, any::<u16>(), any::<u8>()), 1..40),
                                  garbage in prop::collection::vec(any::<u8>(), 0..16),
                                  chunks in prop::collection::vec(1usize..80, 1..6)) {
        let mut stream = Vec::new();
        let mut intact = 0u32;
        for (kind, pos, byte) in &plan {
            let mut f = mocap(*pos as f32);
            match kind {
                0 => intact += 1,
                1 => { let n = 1 + (*pos as usize) % (f.len() - 1); f.truncate(n); }
                2 => {
                    let i = 1 + (*pos as usize) % (f.len() - 1);
                    let flip = if *byte == 0 { 1 } else { *byte };
                    f[i] ^= flip;
                }
                _ => { stream.extend_from_slice(&garbage); }
            }
            if *kind == 3 {
                intact += 1;
            }
            stream.extend_from_slice(&f);
        }
        // A final good frame behind everything: resynchronisation must reach it. A damaged
        // length byte can make the parser wait for up to one maximal frame (280 bytes) before
        // its CRC fails; on a live link more bytes always follow, here 300 idle bytes.
        stream.extend_from_slice(&mocap(0.5));
        stream.extend_from_slice(&[0u8; 300]);
        intact += 1;
        let mut d = Decoder::new(1);
        let accepted = push_chunked_collect(&mut d, &stream, &chunks);
        let got = accepted.len() as u32;
        let c = d.counters();
        // The poses that were sent intact (NWU: x, -0, 1).
        let mut sent: Vec<f32> = plan
            .iter()
            .filter(|(k, _, _)| *k == 0 || *k == 3)
            .map(|(_, pos, _)| *pos as f32)
            .collect();
        sent.push(0.5);
        // A damaged frame may be swallowed together with the next one only when its length
        // byte was damaged. The CRC rejects the damaged frames themselves, but a window that
        // starts at a damaged frame's marker and ends inside the next frame passes a 16-bit
        // CRC by chance with probability 2^-16 (proptest found one: x = 31023 behind a frame
        // truncated to 13 bytes, kept in sil_link_fuzz.proptest-regressions). Such a
        // collision decodes to a pose that was never sent; every other accepted frame is one of
        // the intact ones, and at least one (the final one, unless a collision swallowed it) is decoded.
        let genuine = |m: &Inbound| match m {
            Inbound::Pose { position, .. } => {
                position.y == 0.0 && position.z == 1.0 && sent.contains(&position.x)
            }
            _ => false,
        };
        let genuine_count = accepted.iter().filter(|m| genuine(m)).count() as u32;
        let collisions = got - genuine_count;
        let damaged = plan.iter().filter(|(k, _, _)| *k == 1 || *k == 2).count() as u32;
        prop_assert!(collisions <= damaged, "{} collisions, {} damaged", collisions, damaged);
        prop_assert!(genuine_count <= intact, "{} > {}", genuine_count, intact);
        prop_assert_eq!(c.frames_ok, got);
        prop_assert!(genuine_count >= 1);
        if damaged > 0 {
            prop_assert!(c.frames_malformed + c.frames_dropped + c.bytes_discarded > 0 || got < intact);
        }
    }
}

/// Deterministic: a stream of 100 frames with every tenth corrupted, pushed one byte at a time.
#[test]
fn every_tenth_frame_corrupted() {
    let mut stream = Vec::new();
    for k in 0..100u8 {
        let mut f = mocap(f32::from(k));
        if k % 10 == 0 {
            let n = f.len();
            f[n - 3] ^= 0xFF; // payload byte: the CRC fails
        }
        stream.extend_from_slice(&f);
    }
    let mut d = Decoder::new(1);
    let got = push_chunked(&mut d, &stream, &[1]);
    assert_eq!(got, 90);
    let c = d.counters();
    assert_eq!(c.frames_ok, 90);
    assert!(c.frames_malformed >= 10);
    // Unused but valid messages are dropped, not malformed.
    let hb = frame(&MavMessage::HEARTBEAT(HEARTBEAT_DATA::default()), 1);
    let mut d = Decoder::new(1);
    push_chunked(&mut d, &hb, &[3]);
    assert_eq!(
        (d.counters().frames_dropped, d.counters().frames_malformed),
        (1, 0)
    );
}
