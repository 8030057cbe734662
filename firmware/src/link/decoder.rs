//! The MAVLink 2 frame parser: bytes in any chunking to checked frames (CRC, signature,
//! addressing), never panicking, counting every failure.

use mavlink::dialects::common::{
    MavMessage, ATT_POS_MOCAP_DATA, ODOMETRY_DATA, SETUP_SIGNING_DATA,
};
use mavlink::{Message, MessageData};

use super::interpret::{self, Address, Interpretation};
use super::signing::{Check, Signing, SigningConfig, SIGNED_FLAG};
use super::{
    Inbound, LinkCounters, LinkTrust, Sender, AUTOPILOT_COMPONENT, HEADER, MAX_FRAME, SIGNATURE,
    STX,
};

/// Result of looking at the head of the buffer.
enum Step {
    /// Nothing to do until the buffer holds this many bytes.
    NeedMore(usize),
    /// Drop `n` bytes from the front; `true` when they were a frame accepted as a message (put
    /// in the caller's `out`).
    Consume(usize, bool),
}

/// The MAVLink 2 stream decoder. Holds at most one partial frame ([`MAX_FRAME`] bytes).
#[derive(Clone, Debug)]
pub struct Decoder {
    buf: [u8; MAX_FRAME],
    len: usize,
    /// The buffer length the head frame needs before [`Decoder::poll`] can make progress (0:
    /// look now). Saves re-parsing the header on every byte of a frame.
    need: usize,
    address: Address,
    /// The key, the replay memory and the link's trust (who may send `SETUP_SIGNING`).
    signing: Signing,
    counters: LinkCounters,
}

impl Decoder {
    /// A decoder for a vehicle with MAVLink system id `system_id` and component id
    /// [`AUTOPILOT_COMPONENT`], without signing, on an untrusted link (commands and setpoints
    /// addressed to another system or component are dropped; 0 is broadcast).
    pub fn new(system_id: u8) -> Self {
        Self::with_address(system_id, AUTOPILOT_COMPONENT, None)
    }

    /// A decoder for (`system_id`, `component_id`) with `signing` (`None`: no key; signed
    /// frames are then dropped, see [`super::signing`]), on an untrusted link
    /// ([`Decoder::with_trust`] marks a wired one).
    pub fn with_address(system_id: u8, component_id: u8, signing: Option<SigningConfig>) -> Self {
        Self {
            buf: [0; MAX_FRAME],
            len: 0,
            need: 0,
            address: Address {
                system: system_id,
                component: component_id,
            },
            signing: Signing::new(signing),
            counters: LinkCounters::default(),
        }
    }

    /// This decoder on a link of trust `trust`, as the board built it: [`LinkTrust::Trusted`]
    /// only for a wired console that no stranger can transmit on.
    pub fn with_trust(mut self, trust: LinkTrust) -> Self {
        self.signing.set_trust(trust);
        self
    }

    /// The trust of the link this decoder reads.
    pub fn trust(&self) -> LinkTrust {
        self.signing.trust()
    }

    /// Whether a signing key is installed.
    pub fn signing_active(&self) -> bool {
        self.signing.active()
    }

    /// Installs a signing key, or replaces the one installed, with the signing clock at least
    /// `initial_timestamp` \[10 µs since 2015-01-01\]. The replay memory (the clock, each
    /// stream's last timestamp) is kept, so nothing recorded before a change can be replayed
    /// after it. Returns false, changing nothing, for the all-zero key (MAVLink's "no key").
    ///
    /// Whether a `SETUP_SIGNING` may do this is the caller's decision, from the
    /// [`super::SetupAuthority`] the decoder gave it: the pipeline takes only a trusted link's
    /// or one signed with the key in force.
    pub fn install_signing_key(&mut self, config: SigningConfig, initial_timestamp: u64) -> bool {
        self.signing.install(config, initial_timestamp)
    }

    /// Signs the frame `out[..len]` that [`super::encode`] or [`super::encode_data`] wrote,
    /// when a key is installed: returns its new length (`len` + [`SIGNATURE`]), `len` without a
    /// key, 0 (nothing changed) when `out` has no room for the signature or `out[..len]` is not
    /// a frame.
    pub fn sign(&mut self, out: &mut [u8], len: usize) -> usize {
        if len < 1 + HEADER + 2 || len > out.len() || out[0] != STX {
            return 0;
        }
        let msgid = u32::from_le_bytes([out[7], out[8], out[9], 0]);
        self.signing.sign(out, len, MavMessage::extra_crc(msgid))
    }

    /// The bytes held back, waiting for the rest of a frame.
    #[cfg(test)]
    pub(super) fn pending(&self) -> &[u8] {
        &self.buf[..self.len]
    }

    /// True when no byte is held back: [`Decoder::feed`] of nothing then completes nothing.
    pub fn holds_nothing(&self) -> bool {
        self.len == 0
    }

    /// Counters so far.
    pub fn counters(&self) -> LinkCounters {
        self.counters
    }

    /// Feeds bytes (any chunking); calls `accept` for every message accepted, in order, as soon
    /// as the byte that completes it is in. Nothing is buffered between messages, so a burst of
    /// frames released at once (after a corrupted length byte held them back) loses none.
    pub fn push(&mut self, mut bytes: &[u8], mut accept: impl FnMut(Inbound)) {
        while let (used, Some(m)) = self.feed(bytes) {
            bytes = &bytes[used..];
            accept(m);
        }
    }

    /// Feeds bytes from the front of `bytes` until one completes a message: returns how many
    /// it took and that message, or `(bytes.len(), None)` when all of them completed none.
    /// Call again with the rest after a message. Exactly as [`Decoder::push_byte`] then
    /// [`Decoder::poll`] per byte, but a frame that arrives whole while nothing is held back is
    /// parsed where it is (no copy into the buffer), the bytes a partial frame still needs go
    /// in as one copy, and its header is parsed once, not once per byte.
    pub fn feed(&mut self, bytes: &[u8]) -> (usize, Option<Inbound>) {
        let mut message = None;
        let used = self.feed_into(bytes, &mut message);
        (used, message)
    }

    /// [`Decoder::feed`] with the message put in `out` (which must be `None`) instead of
    /// returned: the pipeline's way, which spares the MCU a copy of the message.
    pub(crate) fn feed_into(&mut self, bytes: &[u8], out: &mut Option<Inbound>) -> usize {
        let mut used = 0;
        loop {
            if self.poll_into(out) {
                return used;
            }
            let rest = &bytes[used..];
            if rest.is_empty() {
                return used;
            }
            if self.len == 0 {
                // Nothing held back: look at the input where it is, without copying it into
                // the buffer. `examine`'s verdict on a longer run of bytes is the one it gives
                // the byte-by-byte buffer at the first length where it is not `NeedMore` (it
                // reads a frame's own bytes only), so the messages and counters are the same.
                match examine(
                    &mut self.counters,
                    &mut self.signing,
                    self.address,
                    rest,
                    out,
                ) {
                    Step::Consume(n, accepted) => {
                        used += n.min(rest.len());
                        if accepted {
                            return used;
                        }
                        continue;
                    }
                    Step::NeedMore(n) => {
                        // A partial frame (shorter than `n` ≤ MAX_FRAME): held back whole.
                        self.buf[..rest.len()].copy_from_slice(rest);
                        self.len = rest.len();
                        self.need = n;
                        return bytes.len();
                    }
                }
            }
            // `poll` cannot progress before `need` bytes; a full buffer (which `poll` always
            // empties in part, since no frame is longer) goes through `push_byte`.
            let n = self
                .need
                .saturating_sub(self.len)
                .max(1)
                .min(MAX_FRAME - self.len)
                .min(rest.len());
            if n == 0 {
                self.push_byte(rest[0]);
                used += 1;
            } else {
                self.buf[self.len..self.len + n].copy_from_slice(&rest[..n]);
                self.len += n;
                used += n;
            }
        }
    }

    /// Feeds one byte of the stream. Drain [`Decoder::poll`] (until `None`) before the next
    /// byte: one byte can release several frames at once. A caller that does not drain loses
    /// the oldest byte when the buffer is full ([`MAX_FRAME`]), counted in `bytes_discarded`,
    /// rather than overflowing.
    pub fn push_byte(&mut self, b: u8) {
        if self.len == MAX_FRAME {
            self.buf.copy_within(1.., 0);
            self.len -= 1;
            self.need = 0;
            self.counters.bytes_discarded = self.counters.bytes_discarded.saturating_add(1);
        }
        self.buf[self.len] = b;
        self.len += 1;
    }

    /// The next message the bytes fed so far complete, in stream order, or `None` when more
    /// bytes are needed. Every frame looked at is counted (ok, dropped, malformed).
    pub fn poll(&mut self) -> Option<Inbound> {
        let mut message = None;
        self.poll_into(&mut message);
        message
    }

    /// [`Decoder::poll`] into `out` (which must be `None`): true when a message was put there.
    fn poll_into(&mut self, out: &mut Option<Inbound>) -> bool {
        while self.len > 0 && self.len >= self.need {
            let Self {
                buf,
                len,
                address,
                signing,
                counters,
                ..
            } = self;
            match examine(counters, signing, *address, &buf[..*len], out) {
                Step::NeedMore(n) => {
                    self.need = n;
                    return false;
                }
                Step::Consume(n, accepted) => {
                    self.need = 0;
                    let n = n.min(self.len);
                    self.buf.copy_within(n..self.len, 0);
                    self.len -= n;
                    if accepted {
                        return true;
                    }
                }
            }
        }
        false
    }
}

/// The verdict on `buf`, the bytes from the head of the stream on (the decoder's buffer, or
/// the input itself when nothing is held back): what to drop, and whether they were a message
/// (then put in `out`, which must be `None`), or how many bytes the head frame needs. Counts
/// what it drops.
#[inline(always)]
fn examine(
    counters: &mut LinkCounters,
    signing: &mut Signing,
    address: Address,
    buf: &[u8],
    out: &mut Option<Inbound>,
) -> Step {
    if buf.is_empty() {
        return Step::NeedMore(1);
    }
    if buf[0] != STX {
        let skip = buf.iter().position(|&b| b == STX).unwrap_or(buf.len());
        counters.bytes_discarded = counters.bytes_discarded.saturating_add(skip as u32);
        return Step::Consume(skip, false);
    }
    if buf.len() < 3 {
        return Step::NeedMore(3);
    }
    let incompat = buf[2];
    if incompat & !0x01 != 0 {
        // Unknown incompatibility flag (e.g. 32-bit system ids): we must not parse it.
        counters.frames_malformed = counters.frames_malformed.saturating_add(1);
        return Step::Consume(1, false);
    }
    let total = frame_length(buf[1], incompat);
    // A checked frame that starts inside this one and ends before it is what was sent: this
    // marker was false, or its frame was cut short (a corrupted length byte, a truncated
    // frame). Without this, its declared length would hold back the frames behind it (a
    // kill, say) until that many more bytes arrived, which on a quiet link may be never.
    match later_frame(buf, total) {
        Ok(()) => {
            counters.frames_malformed = counters.frames_malformed.saturating_add(1);
            return Step::Consume(1, false);
        }
        Err(need) if buf.len() < total => return Step::NeedMore(need),
        Err(_) => {}
    }
    let msgid = frame_msgid(buf);
    let Some(extra) = crc_extra(msgid) else {
        // Not in the common dialect: its CRC cannot be checked, so it may as well be a
        // false marker inside other data. Skipping only the marker keeps the frames behind
        // it (a real unknown frame is then rescanned, which costs at most a few spurious
        // malformed counts if its payload holds 0xFD).
        counters.frames_dropped = counters.frames_dropped.saturating_add(1);
        return Step::Consume(1, false);
    };
    if !crc_holds(&buf[..total], extra) {
        counters.frames_malformed = counters.frames_malformed.saturating_add(1);
        // A false marker or a corrupted frame: look again from the next byte.
        return Step::Consume(1, false);
    }
    let signed = incompat & SIGNED_FLAG != 0;
    let crc_at = 1 + HEADER + buf[1] as usize;
    let sender = Sender {
        system: buf[5],
        component: buf[6],
    };
    let check = signing.check(
        &buf[..total],
        signed,
        sender.system,
        sender.component,
        interpret::is_command(msgid),
    );
    let counter = match check {
        Check::Accept => None,
        // The owner's way back in when the key is lost: over the wired console an unsigned
        // SETUP_SIGNING is still heard (the pipeline then takes it only while disarmed). On
        // this cold path only, so the frames that pass cost no more.
        Check::UnsignedRefused
            if msgid == SETUP_SIGNING_DATA::ID && signing.trust() == LinkTrust::Trusted =>
        {
            None
        }
        Check::SignedWithoutKey => Some(&mut counters.signed_without_key),
        Check::BadSignature => Some(&mut counters.bad_signature),
        Check::Stale => Some(&mut counters.stale_signature),
        Check::UnsignedRefused => Some(&mut counters.unsigned_refused),
    };
    if let Some(c) = counter {
        *c = c.saturating_add(1);
        return Step::Consume(total, false);
    }
    let payload = &buf[1 + HEADER..crc_at];
    if msgid == SETUP_SIGNING_DATA::ID {
        // Who may change the key, out of line: the one test every frame pays for it.
        let accepted = setup_signing(counters, signing, address, sender, payload, signed, out);
        return Step::Consume(total, accepted);
    }
    let interpretation = interpret::interpret(address, sender, msgid, payload, out);
    Step::Consume(total, count(counters, interpretation))
}

/// The length \[bytes\] of a frame whose header declares `payload_len` and flags `incompat`.
#[inline(always)]
fn frame_length(payload_len: u8, incompat: u8) -> usize {
    let signed = incompat & SIGNED_FLAG != 0;
    1 + HEADER + payload_len as usize + 2 + if signed { SIGNATURE } else { 0 }
}

/// The message id of the frame at the head of `buf` (which holds its header).
#[inline(always)]
fn frame_msgid(buf: &[u8]) -> u32 {
    u32::from_le_bytes([buf[7], buf[8], buf[9], 0])
}

/// The CRC seed of message `msgid`, `None` outside the common dialect.
#[inline(always)]
fn crc_extra(msgid: u32) -> Option<u8> {
    // The pose messages, the stream's usual frames, without the call into the dialect's
    // table (the same constants).
    let extra = match msgid {
        ATT_POS_MOCAP_DATA::ID => ATT_POS_MOCAP_DATA::EXTRA_CRC,
        ODOMETRY_DATA::ID => ODOMETRY_DATA::EXTRA_CRC,
        _ => MavMessage::extra_crc(msgid),
    };
    (extra != 0).then_some(extra)
}

/// Whether the whole frame `frame` (marker to signature) carries the CRC of its header and
/// payload seeded with `extra`.
#[inline(always)]
fn crc_holds(frame: &[u8], extra: u8) -> bool {
    let crc_at = 1 + HEADER + frame[1] as usize;
    let crc = u16::from_le_bytes([frame[crc_at], frame[crc_at + 1]]);
    super::crc::frame_crc(&frame[1..crc_at], extra) == crc
}

/// Looks inside the head frame (`buf[0]` its marker, `total` its declared length; `buf` may
/// hold less of it, or more than it) for a frame that starts after the head's marker, ends
/// before the head does, and checks (a known message with a matching CRC; its signature is
/// checked only once it is the head). `Ok(())` when there is one in the bytes held; else
/// `Err(n)`: the least buffer length at which one could complete, at most `total` (where the
/// head itself is judged).
///
/// The verdict at each buffer length depends only on the bytes up to it, and `n` is exact,
/// so the byte-at-a-time decoder and one fed whole runs give the same messages and counts.
/// A real frame whose payload carries a whole checked frame that ends before it is given up
/// for that inner frame: a 16-bit CRC collision on data built for it, which buys a sender
/// nothing it could not send plainly.
#[inline(never)]
fn later_frame(buf: &[u8], total: usize) -> Result<(), usize> {
    let seen = buf.len().min(total);
    // A marker not yet received (at `seen` or later) ends no earlier than this.
    let mut need = seen + SHORTEST_FRAME;
    // A frame that ends before the head starts before `total - SHORTEST_FRAME`.
    let starts = buf
        .get(1..seen.min(total.saturating_sub(SHORTEST_FRAME)))
        .unwrap_or(&[]);
    if each_marker(starts, |offset| {
        inner_frame(buf, offset + 1, (seen, total), &mut need)
    }) {
        Ok(())
    } else {
        Err(need.min(total))
    }
}

/// The shortest frame \[bytes\]: marker, header and CRC, no payload.
const SHORTEST_FRAME: usize = 1 + HEADER + 2;

/// [`later_frame`] at the marker `buf[at]`: true when a frame starts there, ends before the
/// head's `total`, is all in (`seen` bytes are) and checks; else lowers `need` to where it
/// could complete. Out of line: most frames hold no marker byte, and the search stays short.
#[cold]
#[inline(never)]
fn inner_frame(buf: &[u8], at: usize, (seen, total): (usize, usize), need: &mut usize) -> bool {
    if at + 3 > seen {
        // Its length is not in yet.
        *need = (*need).min(at + SHORTEST_FRAME);
        return false;
    }
    let incompat = buf[at + 2];
    if incompat & !0x01 != 0 {
        return false;
    }
    let end = at + frame_length(buf[at + 1], incompat);
    if end >= total {
        return false;
    }
    if end > seen {
        *need = (*need).min(end);
        return false;
    }
    let frame = &buf[at..end];
    crc_extra(frame_msgid(frame)).is_some_and(|extra| crc_holds(frame, extra))
}

/// Calls `visit(i)` for each `i` with `bytes[i]` the start marker, in order, until one returns
/// true; returns whether one did. Four bytes at a time (a word with no marker byte is passed
/// over with a few instructions): every frame's bytes are searched, and they rarely hold one.
#[inline(always)]
fn each_marker(bytes: &[u8], mut visit: impl FnMut(usize) -> bool) -> bool {
    const ONES: u32 = 0x0101_0101;
    const MARKERS: u32 = ONES * STX as u32;
    let mut words = bytes.chunks_exact(4);
    let mut base = 0;
    for word in &mut words {
        let x = u32::from_le_bytes([word[0], word[1], word[2], word[3]]) ^ MARKERS;
        // Non-zero exactly when a byte of `x` is zero, i.e. a byte of the word is the marker.
        if x.wrapping_sub(ONES) & !x & (ONES << 7) != 0 {
            for (i, &b) in word.iter().enumerate() {
                if b == STX && visit(base + i) {
                    return true;
                }
            }
        }
        base += 4;
    }
    for (i, &b) in words.remainder().iter().enumerate() {
        if b == STX && visit(base + i) {
            return true;
        }
    }
    false
}

/// Counts a frame that passed the CRC and signature checks by what its interpretation made of
/// it; true when it was accepted as a message.
#[inline(always)]
fn count(counters: &mut LinkCounters, interpretation: Interpretation) -> bool {
    match interpretation {
        Interpretation::Accepted => {
            counters.frames_ok = counters.frames_ok.saturating_add(1);
            true
        }
        Interpretation::Ignored => {
            counters.frames_dropped = counters.frames_dropped.saturating_add(1);
            false
        }
        Interpretation::Malformed => {
            counters.frames_malformed = counters.frames_malformed.saturating_add(1);
            false
        }
    }
}

/// [`examine`]'s end for a `SETUP_SIGNING` frame (`payload`, `signed`: it carried a signature)
/// that passed the signature check: interprets it, marks who may have sent it (the link's
/// trust, or a signature with the key in force: without a key, signed frames were dropped
/// before) for the pipeline, which refuses an unauthenticated one aloud, and counts it. True
/// when it was accepted as a message (put in `out`).
#[inline(never)]
fn setup_signing(
    counters: &mut LinkCounters,
    signing: &Signing,
    address: Address,
    sender: Sender,
    payload: &[u8],
    signed: bool,
    out: &mut Option<Inbound>,
) -> bool {
    let interpretation =
        interpret::interpret(address, sender, SETUP_SIGNING_DATA::ID, payload, out);
    if let Some(Inbound::SetupSigning { authority, .. }) = out {
        *authority = signing.setup_authority(signed);
    }
    count(counters, interpretation)
}
