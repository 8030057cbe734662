//! MAVLink 2 message signing: checking the signature of what comes in, signing what goes out.
//!
//! A signed frame carries 13 more bytes: a link id, a 48-bit timestamp (units of 10 µs since
//! 2015-01-01 00:00 UTC) and the first 6 bytes of SHA-256 over the 32-byte secret key followed by
//! the frame from its start marker to its link id and timestamp. The threat it addresses:
//! anyone who can put bytes on the radio link (the same radio, a second ground station, a
//! replay of a recording) can otherwise arm, kill, move or re-key the vehicle. With a key,
//! a frame is used only if its signature matches and its timestamp is after the last one of its
//! stream (link id, system, component), so a recorded frame cannot be played again.
//!
//! Rules (MAVLink 2 message signing, <https://mavlink.io/en/guide/message_signing.html>):
//! - no key: signed frames are dropped (a system that does not check signatures must not act
//!   on them), unsigned ones are used;
//! - a key: a bad signature or a stale timestamp drops the frame; unsigned commands, setpoints
//!   and parameter sets are refused, and so is an unsigned `SETUP_SIGNING` except on a link
//!   trusted at build time ([`super::LinkTrust`]); unsigned poses and sensor samples are used
//!   only if [`SigningConfig::accept_unsigned_sensors`] (a motion-capture bridge that cannot
//!   sign); everything the vehicle sends is signed.
//!
//! Who may install or change the key with `SETUP_SIGNING` is the link's business, not this
//! module's: the decoder tells the pipeline ([`super::SetupAuthority`]) whether the frame came
//! over a trusted (wired) link or was signed with the key in force; anything else is refused,
//! so a stranger on the radio cannot install a key before the owner and lock them out.
//!
//! The vehicle has no real-time clock: its signing clock is the largest timestamp it has
//! accepted (or been given by `SETUP_SIGNING`), plus one per frame it signs. After a restart a
//! ground station should send it a signed frame (e.g. its `HEARTBEAT`) before it expects the
//! vehicle's frames to pass its own replay check.

use sha2::{Digest, Sha256};

use super::{LinkTrust, SetupAuthority};

/// Signature block length: link id (1), timestamp (6), signature (6).
pub const SIGNATURE: usize = 13;
/// Streams whose last timestamps are remembered; beyond that the oldest is forgotten (it then
/// gets the new-stream rule: at most a minute behind the signing clock).
const STREAMS: usize = 8;
/// One minute in signing-timestamp units (10 µs).
const ONE_MINUTE: u64 = 60 * 100_000;
/// `incompat_flags` bit: the frame is signed.
pub(super) const SIGNED_FLAG: u8 = 0x01;

/// A signing set-up: the key, the link id the vehicle signs with, and whether unsigned poses
/// and sensor samples are used.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SigningConfig {
    /// The 32-byte secret key shared with the ground station.
    pub key: [u8; 32],
    /// Link id written into the frames the vehicle signs.
    pub link_id: u8,
    /// Use unsigned poses (`ODOMETRY`, `ATT_POS_MOCAP`, `VISION_POSITION_ESTIMATE`) and
    /// `HIL_SENSOR` samples; commands must be signed whatever this says.
    pub accept_unsigned_sensors: bool,
}

/// Verdict on one frame whose CRC is good.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Check {
    /// Use it.
    Accept,
    /// Signed, and the vehicle has no key.
    SignedWithoutKey,
    /// Signed with another key (or corrupted behind a valid CRC).
    BadSignature,
    /// Validly signed but not newer than its stream's last frame: a replay.
    Stale,
    /// Unsigned, and signing is required for this message.
    UnsignedRefused,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Stream {
    link_id: u8,
    system: u8,
    component: u8,
    timestamp: u64,
}

/// The signing state of one link.
#[derive(Clone, Debug, Default)]
pub(super) struct Signing {
    config: Option<SigningConfig>,
    /// Whether the link's medium is the owner's alone: who may set the key. Kept here, with
    /// the state the decoder already carries into every frame, so that the frames that are
    /// not `SETUP_SIGNING` do not carry it too.
    trust: LinkTrust,
    /// The vehicle's signing clock \[10 µs since 2015-01-01\].
    timestamp: u64,
    streams: heapless::Vec<Stream, STREAMS>,
}

/// The first 6 bytes of SHA-256(key ‖ `signed_part`): `signed_part` is the frame from its
/// start marker to the end of its timestamp (everything but the signature value).
fn signature(key: &[u8; 32], signed_part: &[u8]) -> [u8; 6] {
    let digest = Sha256::new()
        .chain_update(key)
        .chain_update(signed_part)
        .finalize();
    let mut s = [0u8; 6];
    s.copy_from_slice(&digest[..6]);
    s
}

fn timestamp_of(block: &[u8]) -> u64 {
    let mut t = [0u8; 8];
    t[..6].copy_from_slice(&block[1..7]);
    u64::from_le_bytes(t)
}

impl Signing {
    /// Signing with `config`, or none.
    pub(super) fn new(config: Option<SigningConfig>) -> Self {
        Self {
            config,
            ..Self::default()
        }
    }

    /// Whether a key is installed.
    pub(super) fn active(&self) -> bool {
        self.config.is_some()
    }

    /// The link's trust.
    pub(super) fn trust(&self) -> LinkTrust {
        self.trust
    }

    /// Sets the link's trust (where the board builds the link).
    pub(super) fn set_trust(&mut self, trust: LinkTrust) {
        self.trust = trust;
    }

    /// What entitles a `SETUP_SIGNING` whose frame passed [`Signing::check`] (`signed`: it
    /// carried a signature) to change the key: a signed one passed with the key in force
    /// (without a key, signed frames are dropped).
    pub(super) fn setup_authority(&self, signed: bool) -> SetupAuthority {
        match (self.trust, signed) {
            (LinkTrust::Trusted, _) => SetupAuthority::TrustedLink,
            (LinkTrust::Untrusted, true) => SetupAuthority::SignedWithCurrentKey,
            (LinkTrust::Untrusted, false) => SetupAuthority::Unauthenticated,
        }
    }

    /// Installs `config`, replacing any key installed, with the signing clock at least
    /// `initial_timestamp`. Neither the clock nor the streams' last timestamps go back, so a
    /// frame recorded before a change cannot be replayed after it, not even if its key comes
    /// back: a ground station keeps its timestamps increasing across a change of key, as
    /// MAVLink's signing asks anyway. Refused (returns false, nothing changed) for an all-zero
    /// key (MAVLink's "no key").
    pub(super) fn install(&mut self, config: SigningConfig, initial_timestamp: u64) -> bool {
        if config.key == [0; 32] {
            return false;
        }
        self.config = Some(config);
        self.timestamp = self.timestamp.max(initial_timestamp);
        true
    }

    /// Checks a whole frame (`frame`: start marker to its last byte) from (`system`,
    /// `component`) whose CRC is good. `command`: a message that must be signed whenever
    /// signing is active; any other may go unsigned only if
    /// [`SigningConfig::accept_unsigned_sensors`].
    #[inline(always)]
    pub(super) fn check(
        &mut self,
        frame: &[u8],
        signed: bool,
        system: u8,
        component: u8,
        command: bool,
    ) -> Check {
        // Without a key (the usual link), decided inline; the keyed rules out of line.
        if self.config.is_none() {
            return if signed {
                Check::SignedWithoutKey
            } else {
                Check::Accept
            };
        }
        self.check_keyed(frame, signed, system, component, command)
    }

    /// [`Signing::check`] with a key installed.
    #[inline(never)]
    fn check_keyed(
        &mut self,
        frame: &[u8],
        signed: bool,
        system: u8,
        component: u8,
        command: bool,
    ) -> Check {
        let Some(config) = self.config else {
            return if signed {
                Check::SignedWithoutKey
            } else {
                Check::Accept
            };
        };
        if !signed {
            return if command || !config.accept_unsigned_sensors {
                Check::UnsignedRefused
            } else {
                Check::Accept
            };
        }
        let (signed_part, value) = frame.split_at(frame.len() - 6);
        if signature(&config.key, signed_part) != value {
            return Check::BadSignature;
        }
        let block = &frame[frame.len() - SIGNATURE..];
        let (link_id, timestamp) = (block[0], timestamp_of(block));
        let known = self
            .streams
            .iter_mut()
            .find(|s| (s.link_id, s.system, s.component) == (link_id, system, component));
        match known {
            Some(s) if timestamp <= s.timestamp => return Check::Stale,
            Some(s) => s.timestamp = timestamp,
            None if timestamp.saturating_add(ONE_MINUTE) < self.timestamp => return Check::Stale,
            None => {
                let stream = Stream {
                    link_id,
                    system,
                    component,
                    timestamp,
                };
                if self.streams.is_full() {
                    // Forget the stream heard from longest ago.
                    if let Some(oldest) =
                        (0..self.streams.len()).min_by_key(|&i| self.streams[i].timestamp)
                    {
                        self.streams.swap_remove(oldest);
                    }
                }
                // Room was just made: this cannot fail.
                let _ = self.streams.push(stream);
            }
        }
        self.timestamp = self.timestamp.max(timestamp);
        Check::Accept
    }

    /// Signs the unsigned frame `out[..len]` (start marker to CRC) in place, message `msgid`
    /// with CRC extra `crc_extra`: sets the signed flag, recomputes the CRC and appends the
    /// signature block. Returns the new length; `len` unchanged when there is no key; 0 when
    /// `out` has no room for the block (nothing changed).
    pub(super) fn sign(&mut self, out: &mut [u8], len: usize, crc_extra: u8) -> usize {
        let Some(config) = self.config else {
            return len;
        };
        if len < 12 || len + SIGNATURE > out.len() {
            return 0;
        }
        out[2] |= SIGNED_FLAG;
        let crc_at = len - 2;
        let crc = super::crc::frame_crc(&out[1..crc_at], crc_extra);
        out[crc_at..len].copy_from_slice(&crc.to_le_bytes());
        self.timestamp += 1;
        out[len] = config.link_id;
        out[len + 1..len + 7].copy_from_slice(&self.timestamp.to_le_bytes()[..6]);
        let value = signature(&config.key, &out[..len + 7]);
        out[len + 7..len + SIGNATURE].copy_from_slice(&value);
        len + SIGNATURE
    }
}
