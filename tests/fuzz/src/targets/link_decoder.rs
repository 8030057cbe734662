//! The MAVLink 2 stream decoder ([`firmware::link::Decoder`]) on arbitrary bytes.
//!
//! Input: byte 0 seeds the chunk lengths, the rest is the stream. Invariants:
//! - no panic;
//! - the same stream gives the same messages and counters whether it is fed at once, byte by
//!   byte (`push_byte` and `poll`), or in chunks of 1 to 64 bytes (the UART DMA hands over
//!   arbitrary pieces);
//! - `frames_ok` equals the number of messages handed out, and every counter is monotone
//!   from chunk to chunk;
//! - a decoder cannot discard more bytes than it was given.

use firmware::link::{Decoder, Inbound, LinkCounters};

/// The vehicle's system id (the default build's).
const SYSTEM_ID: u8 = 1;

/// Whether two message lists are the same. `Inbound`'s `PartialEq` is false for NaN fields,
/// which are legal here (the estimator refuses them later): messages it calls different are
/// compared by their debug text.
fn same(a: &[Inbound], b: &[Inbound]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(x, y)| x == y || format!("{x:?}") == format!("{y:?}"))
}

fn counters_monotone(before: &LinkCounters, after: &LinkCounters) -> bool {
    after.frames_ok >= before.frames_ok
        && after.frames_dropped >= before.frames_dropped
        && after.frames_malformed >= before.frames_malformed
        && after.bytes_discarded >= before.bytes_discarded
}

/// Runs the target on one input; panics on a broken invariant.
pub fn run(data: &[u8]) {
    let Some((&seed, stream)) = data.split_first() else {
        return;
    };

    let mut whole = Decoder::new(SYSTEM_ID);
    let mut at_once = Vec::new();
    whole.push(stream, |m| at_once.push(m));

    let mut bytewise = Decoder::new(SYSTEM_ID);
    let mut one_by_one = Vec::new();
    for &b in stream {
        bytewise.push_byte(b);
        while let Some(m) = bytewise.poll() {
            one_by_one.push(m);
        }
    }

    let mut chunked = Decoder::new(SYSTEM_ID);
    let mut in_chunks = Vec::new();
    let mut rest = stream;
    let mut state = u32::from(seed) | 0x100;
    while !rest.is_empty() {
        // xorshift: chunk lengths 1..=64 that vary along the stream.
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        let n = (state % 64 + 1) as usize;
        let (chunk, tail) = rest.split_at(n.min(rest.len()));
        let before = chunked.counters();
        chunked.push(chunk, |m| in_chunks.push(m));
        let after = chunked.counters();
        assert!(
            counters_monotone(&before, &after),
            "a counter went down: {before:?} -> {after:?}"
        );
        rest = tail;
    }

    let c = whole.counters();
    assert!(
        same(&one_by_one, &at_once),
        "byte-by-byte feeding changed the messages: {one_by_one:?} vs {at_once:?}"
    );
    assert!(
        same(&in_chunks, &at_once),
        "chunked feeding changed the messages: {in_chunks:?} vs {at_once:?}"
    );
    assert_eq!(
        bytewise.counters(),
        c,
        "byte-by-byte feeding changed the counters"
    );
    assert_eq!(
        chunked.counters(),
        c,
        "chunked feeding changed the counters"
    );
    assert_eq!(
        c.frames_ok as usize,
        at_once.len(),
        "frames_ok is not the number of messages handed out"
    );
    assert!(
        c.bytes_discarded as usize <= stream.len(),
        "discarded {} bytes of {}",
        c.bytes_discarded,
        stream.len()
    );
}
