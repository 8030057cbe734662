//! SIL scenario 4: malformed, truncated and random byte streams into the MAVLink link: no
//! panic, frames counted as dropped or malformed, valid frames around them still decoded.

use firmware::config::FlightConfig;
use firmware::link::mavlink::dialects::common::{MavMessage, ATT_POS_MOCAP_DATA, HEARTBEAT_DATA};
use firmware::link::{self, Decoder, MAX_FRAME};
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
    let mut got = 0;
    let mut i = 0;
    let mut k = 0;
    while i < bytes.len() {
        let n = chunks
            .get(k % chunks.len().max(1))
            .copied()
            .unwrap_or(7)
            .max(1);
        let j = (i + n).min(bytes.len());
        d.push(&bytes[i..j], |_| got += 1);
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
        let mut p = FlightPipeline::new(&FlightConfig::paper()).unwrap();
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
        let got = push_chunked(&mut d, &stream, &chunks) as u32;
        let c = d.counters();
        // A damaged frame may be swallowed together with the next one only when its length
        // byte was damaged; the CRC keeps all of them from being accepted. Every accepted frame
        // was intact, and the final one is always decoded.
        prop_assert!(got <= intact, "{} > {}", got, intact);
        prop_assert_eq!(c.frames_ok, got);
        prop_assert!(got >= 1);
        let damaged = plan.iter().filter(|(k, _, _)| *k == 1 || *k == 2).count() as u32;
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
