//! A ground station on UDP in front of the flight software under test, shared by both
//! harnesses: QGroundControl, MAVProxy or a MAVROS bridge talks to the in-process pipeline
//! (software in the loop, [`crate::harness::sil::gcs_udp`]) or to the firmware on QEMU
//! (processor in the loop, [`crate::harness::pil`]) as to a vehicle on a network link.
//!
//! The vehicle's side binds an ephemeral UDP port and sends its telemetry to the ground
//! station's address (PX4 SITL's convention: QGroundControl listens on 14550, and so does
//! `mavproxy.py --master udpin:0.0.0.0:14550`). Whatever arrives on the vehicle's port is
//! checked datagram by datagram ([`check_datagram`]): a datagram that is a run of whole, CRC-valid
//! MAVLink 2 frames of the common dialect goes to the flight software as it is, any other is
//! counted ([`GcsCounters::malformed`]) and dropped. Only whole checked frames go in because the
//! link also carries the simulator's own frames: a partial or false frame would make the
//! firmware's decoder wait for bytes that never complete it and swallow the frames behind it
//! (in processor in the loop, the `HIL_SENSOR` that clocks the lockstep). The sender of the
//! last accepted datagram becomes the peer. The run can be paced to the wall clock
//! ([`GcsUdp::pace`]) so that a person at the ground station sees the vehicle in real time.

use std::net::{SocketAddr, UdpSocket};
use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use firmware::link::mavlink::dialects::common::MavMessage;
use firmware::link::mavlink::Message;
use serde::Serialize;

/// MAVLink 2 start marker.
const STX_V2: u8 = 0xFD;
/// MAVLink 1 start marker (the firmware speaks MAVLink 2 only).
const STX_V1: u8 = 0xFE;
/// Marker, header and CRC around a MAVLink 2 payload \[B\].
const OVERHEAD: usize = 12;
/// Signature after the CRC when `incompat_flags & 1` \[B\].
const SIGNATURE: usize = 13;
/// Largest telemetry datagram the vehicle side sends \[B\]: an Ethernet MTU (1500) less the IPv4
/// and UDP headers, so that telemetry is never fragmented on a real network. Frames are never
/// split across datagrams.
pub const MAX_DATAGRAM: usize = 1472;

/// Why a datagram from the ground station was dropped ([`check_datagram`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Malformed {
    /// Zero bytes.
    Empty,
    /// A MAVLink 1 frame (start marker 0xFE) at this offset: the firmware decodes MAVLink 2 only
    /// (pymavlink: set `MAVLINK20=1`; QGroundControl switches to 2 once it hears the vehicle).
    MavLink1(usize),
    /// No start marker at this offset (garbage, or bytes after the last frame).
    NoMarker(usize),
    /// The frame at this offset runs past the end of the datagram.
    Truncated(usize),
    /// The frame at this offset has incompatibility flags other than signing.
    UnknownFlags(usize),
    /// The frame at this offset has a message id outside the common dialect (its CRC cannot be
    /// checked, and the firmware would not use it).
    NotCommon(usize, u32),
    /// The frame at this offset fails its CRC.
    BadCrc(usize),
}

impl std::fmt::Display for Malformed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Empty => write!(f, "empty datagram"),
            Self::MavLink1(at) => write!(f, "MAVLink 1 frame at byte {at} (MAVLink 2 only)"),
            Self::NoMarker(at) => write!(f, "no MAVLink 2 start marker at byte {at}"),
            Self::Truncated(at) => write!(f, "frame at byte {at} cut by the end of the datagram"),
            Self::UnknownFlags(at) => write!(f, "unknown incompatibility flags at byte {at}"),
            Self::NotCommon(at, id) => {
                write!(
                    f,
                    "message id {id} at byte {at} is not in the common dialect"
                )
            }
            Self::BadCrc(at) => write!(f, "bad CRC in the frame at byte {at}"),
        }
    }
}

/// Checks that `datagram` is a run of whole MAVLink 2 frames (signed or not) of the common
/// dialect, each with a valid CRC, and nothing else. Returns the number of frames. Errors: the
/// first thing wrong, with its byte offset ([`Malformed`]).
pub fn check_datagram(datagram: &[u8]) -> Result<usize, Malformed> {
    if datagram.is_empty() {
        return Err(Malformed::Empty);
    }
    let (mut at, mut frames) = (0, 0);
    while at < datagram.len() {
        let rest = &datagram[at..];
        match rest[0] {
            STX_V2 => {}
            STX_V1 => return Err(Malformed::MavLink1(at)),
            _ => return Err(Malformed::NoMarker(at)),
        }
        if rest.len() < OVERHEAD {
            return Err(Malformed::Truncated(at));
        }
        let incompat = rest[2];
        if incompat & !1 != 0 {
            return Err(Malformed::UnknownFlags(at));
        }
        let crc_at = 10 + usize::from(rest[1]);
        let len = crc_at + 2 + if incompat & 1 != 0 { SIGNATURE } else { 0 };
        if rest.len() < len {
            return Err(Malformed::Truncated(at));
        }
        let id = u32::from_le_bytes([rest[7], rest[8], rest[9], 0]);
        // The common dialect's table gives 0 for ids it does not know (as the firmware's decoder
        // reads it).
        let extra = MavMessage::extra_crc(id);
        if extra == 0 {
            return Err(Malformed::NotCommon(at, id));
        }
        let crc = u16::from_le_bytes([rest[crc_at], rest[crc_at + 1]]);
        if firmware::link::crc::frame_crc(&rest[1..crc_at], extra) != crc {
            return Err(Malformed::BadCrc(at));
        }
        at += len;
        frames += 1;
    }
    Ok(frames)
}

/// What went through the ground-station socket.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct GcsCounters {
    /// Datagrams received from the ground station (accepted or not).
    pub datagrams_in: u64,
    /// MAVLink frames of the accepted datagrams, passed to the flight software.
    pub frames_in: u64,
    /// Datagrams dropped because they were not whole checked frames ([`check_datagram`]).
    pub malformed: u64,
    /// Datagrams of telemetry sent to the ground station (lost ones included: UDP does not say).
    pub datagrams_out: u64,
    /// Bytes of telemetry sent \[B\].
    pub bytes_out: u64,
}

/// What the ground-station link did in a run ([`GcsUdp::summary`]); its `Display` is one line
/// for the printed summary.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct GcsSummary {
    /// The address telemetry went to last (the last valid sender, else the one given).
    pub peer: String,
    /// The counters.
    #[serde(flatten)]
    pub counters: GcsCounters,
    /// The sender of the last malformed datagram and why it was dropped (`None`: none).
    pub last_malformed: Option<String>,
}

impl std::fmt::Display for GcsSummary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let c = &self.counters;
        write!(
            f,
            "ground station {}: {} datagrams in ({} frames passed on, {} malformed dropped), {} \
             datagrams ({} B) of telemetry out",
            self.peer, c.datagrams_in, c.frames_in, c.malformed, c.datagrams_out, c.bytes_out
        )?;
        if let Some(why) = &self.last_malformed {
            write!(f, "; last malformed {why}")?;
        }
        Ok(())
    }
}

/// The vehicle's end of the ground-station link: one UDP socket, the peer it sends to, the
/// counters, and the wall-clock pacing.
pub struct GcsUdp {
    socket: UdpSocket,
    peer: SocketAddr,
    started: Option<Instant>,
    realtime: bool,
    counters: GcsCounters,
    last_malformed: Option<(Malformed, SocketAddr)>,
    /// Receive buffer: the largest UDP payload, so a datagram is never cut silently.
    buf: Vec<u8>,
    /// Telemetry frames queued for the next datagram ([`GcsUdp::queue_frame`]).
    outbox: Vec<u8>,
}

impl GcsUdp {
    /// A non-blocking socket on an ephemeral local port of the same family as `peer`, sending to
    /// `peer`; `realtime`: [`GcsUdp::pace`] holds the run to the wall clock. Errors: the socket
    /// cannot be opened or made non-blocking.
    pub fn open(peer: SocketAddr, realtime: bool) -> Result<Self> {
        let local: SocketAddr = if peer.is_ipv4() {
            ([0, 0, 0, 0], 0).into()
        } else {
            (std::net::Ipv6Addr::UNSPECIFIED, 0).into()
        };
        let socket = UdpSocket::bind(local).context("cannot open the ground-station UDP socket")?;
        socket
            .set_nonblocking(true)
            .context("cannot make the ground-station UDP socket non-blocking")?;
        Ok(Self {
            socket,
            peer,
            started: None,
            realtime,
            counters: GcsCounters::default(),
            last_malformed: None,
            buf: vec![0; 65_536],
            outbox: Vec::new(),
        })
    }

    /// The local address the ground station answers to (the bound, ephemeral port). Errors:
    /// the operating system cannot tell.
    pub fn local_addr(&self) -> Result<SocketAddr> {
        Ok(self.socket.local_addr()?)
    }

    /// Where telemetry goes now: the given address until a ground station has sent a valid
    /// datagram, then the last such sender.
    pub fn peer(&self) -> SocketAddr {
        self.peer
    }

    /// Counters so far.
    pub fn counters(&self) -> GcsCounters {
        self.counters
    }

    /// Why the last malformed datagram was dropped, and who sent it (`None`: none so far).
    pub fn last_malformed(&self) -> Option<(Malformed, SocketAddr)> {
        self.last_malformed
    }

    /// What the link did, for a run's summary.
    pub fn summary(&self) -> GcsSummary {
        GcsSummary {
            peer: self.peer.to_string(),
            counters: self.counters,
            last_malformed: self
                .last_malformed
                .map(|(why, from)| format!("from {from}: {why}")),
        }
    }

    /// Appends the bytes of every datagram waiting that passes [`check_datagram`] to `into`, in
    /// arrival order, each whole (so `into` stays at a frame boundary if it was at one); the
    /// others are counted and dropped. The sender of the last accepted one becomes the peer.
    /// Errors: socket failures other than "nothing waiting" (an ICMP port-unreachable answer to
    /// an earlier send, which means only that no ground station listens yet, is ignored).
    pub fn poll(&mut self, into: &mut Vec<u8>) -> Result<()> {
        loop {
            match self.socket.recv_from(&mut self.buf) {
                Ok((n, from)) => {
                    self.counters.datagrams_in += 1;
                    let datagram = &self.buf[..n];
                    match check_datagram(datagram) {
                        Ok(frames) => {
                            into.extend_from_slice(datagram);
                            self.counters.frames_in += frames as u64;
                            self.peer = from;
                        }
                        Err(why) => {
                            self.counters.malformed += 1;
                            self.last_malformed = Some((why, from));
                        }
                    }
                }
                Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => return Ok(()),
                Err(e) if e.kind() == std::io::ErrorKind::ConnectionRefused => {}
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => return Err(e).context("ground-station UDP receive failed"),
            }
        }
    }

    /// Sends `bytes` (whole frames) to the peer as one datagram; nothing for no bytes. Best
    /// effort: a ground station that is not there yet is not an error, the datagram is lost.
    pub fn send(&mut self, bytes: &[u8]) {
        if !bytes.is_empty() && self.socket.send_to(bytes, self.peer).is_ok() {
            self.counters.datagrams_out += 1;
            self.counters.bytes_out += bytes.len() as u64;
        }
    }

    /// Queues one whole frame of telemetry; sends the queue first if the frame would take it
    /// past [`MAX_DATAGRAM`]. [`GcsUdp::flush`] sends the rest.
    pub fn queue_frame(&mut self, frame: &[u8]) {
        if !self.outbox.is_empty() && self.outbox.len() + frame.len() > MAX_DATAGRAM {
            self.flush();
        }
        self.outbox.extend_from_slice(frame);
    }

    /// Sends the frames queued by [`GcsUdp::queue_frame`], if any, as one datagram.
    pub fn flush(&mut self) {
        let outbox = std::mem::take(&mut self.outbox);
        self.send(&outbox);
        self.outbox = outbox;
        self.outbox.clear();
    }

    /// When pacing, sleeps until the wall clock has run `t_us` \[µs\] since the first call (the
    /// simulation time of the first call is taken as 0): the run never goes faster than real
    /// time. It does nothing when the run is already behind, so a slow flight software (the
    /// emulator) sets the pace itself.
    pub fn pace(&mut self, t_us: u64) {
        if !self.realtime {
            return;
        }
        let start = *self.started.get_or_insert_with(Instant::now);
        let due = start + Duration::from_micros(t_us);
        let now = Instant::now();
        if due > now {
            std::thread::sleep(due - now);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use firmware::link::mavlink::dialects::common::{HEARTBEAT_DATA, PARAM_REQUEST_LIST_DATA};
    use firmware::link::{self};

    fn frame(m: &MavMessage, seq: u8) -> Vec<u8> {
        let mut buf = [0u8; link::MAX_FRAME];
        let n = link::encode(m, 255, 190, seq, &mut buf);
        buf[..n].to_vec()
    }

    /// Given whole frames, one or several in a datagram, then they pass; given a datagram cut,
    /// with garbage after its frames, a broken CRC, MAVLink 1, an unknown id, unknown flags or
    /// nothing, then it is refused with the offset of what is wrong.
    #[test]
    fn only_runs_of_whole_checked_frames_pass() {
        let hb = frame(&MavMessage::HEARTBEAT(HEARTBEAT_DATA::default()), 0);
        let list = frame(
            &MavMessage::PARAM_REQUEST_LIST(PARAM_REQUEST_LIST_DATA {
                target_system: 1,
                target_component: 1,
            }),
            1,
        );
        assert_eq!(check_datagram(&hb), Ok(1));
        let two = [hb.clone(), list.clone()].concat();
        assert_eq!(check_datagram(&two), Ok(2));
        assert_eq!(check_datagram(&[]), Err(Malformed::Empty));
        assert_eq!(
            check_datagram(&two[..two.len() - 1]),
            Err(Malformed::Truncated(hb.len()))
        );
        assert_eq!(check_datagram(&hb[..5]), Err(Malformed::Truncated(0)));
        let mut trailing = hb.clone();
        trailing.push(0);
        assert_eq!(
            check_datagram(&trailing),
            Err(Malformed::NoMarker(hb.len()))
        );
        let mut bad = two.clone();
        let last = bad.len() - 1;
        bad[last] ^= 1;
        assert_eq!(check_datagram(&bad), Err(Malformed::BadCrc(hb.len())));
        let mut v1 = hb.clone();
        v1[0] = STX_V1;
        assert_eq!(check_datagram(&v1), Err(Malformed::MavLink1(0)));
        let mut flags = hb.clone();
        flags[2] = 2;
        assert_eq!(check_datagram(&flags), Err(Malformed::UnknownFlags(0)));
        // An id the common dialect does not have (ArduPilot's 11000, DEVICE_OP_READ).
        let mut unknown = hb.clone();
        unknown[7..10].copy_from_slice(&[0xF8, 0x2A, 0]);
        assert_eq!(
            check_datagram(&unknown),
            Err(Malformed::NotCommon(0, 11_000))
        );
        // A signed frame is the unsigned one plus 13 bytes of signature, flag 1 set.
        let mut signed = hb.clone();
        signed[2] = 1;
        let crc_at = signed.len() - 2;
        let crc = firmware::link::crc::frame_crc(&signed[1..crc_at], MavMessage::extra_crc(0));
        signed[crc_at..].copy_from_slice(&crc.to_le_bytes());
        signed.extend([0u8; SIGNATURE]);
        assert_eq!(check_datagram(&signed), Ok(1));
    }

    /// Given a ground station on localhost that sends a good datagram, a cut one and garbage,
    /// when the vehicle side polls, then only the good one's bytes come out, the two others are
    /// counted as malformed, and the telemetry goes to the good one's sender, never split
    /// inside a frame.
    #[test]
    fn polling_keeps_good_datagrams_and_counts_the_rest() {
        let station = UdpSocket::bind("127.0.0.1:0").unwrap();
        station
            .set_read_timeout(Some(Duration::from_secs(2)))
            .unwrap();
        // Told another address first: the first valid datagram's sender becomes the peer.
        let mut gcs = GcsUdp::open("127.0.0.1:9".parse().unwrap(), false).unwrap();
        let vehicle = ("127.0.0.1", gcs.local_addr().unwrap().port());
        // A non-zero last field: MAVLink 2 does not trim the payload, the frame is 21 B.
        let hb = frame(
            &MavMessage::HEARTBEAT(HEARTBEAT_DATA {
                mavlink_version: 3,
                ..Default::default()
            }),
            0,
        );
        assert_eq!(hb.len(), 21);
        station.send_to(&hb[..hb.len() - 3], vehicle).unwrap();
        station.send_to(&hb, vehicle).unwrap();
        station.send_to(b"hello", vehicle).unwrap();
        let mut into = Vec::new();
        // Localhost delivers at once, but give the kernel a moment anyway.
        for _ in 0..100 {
            gcs.poll(&mut into).unwrap();
            if gcs.counters().datagrams_in == 3 {
                break;
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        assert_eq!(into, hb);
        let c = gcs.counters();
        assert_eq!((c.datagrams_in, c.frames_in, c.malformed), (3, 1, 2));
        assert_eq!(gcs.peer(), station.local_addr().unwrap());
        assert!(matches!(
            gcs.last_malformed(),
            Some((Malformed::NoMarker(0), _))
        ));
        // 60 heartbeats (21 B each) make 1260 B: one datagram; 80 make two, cut between frames.
        for _ in 0..80 {
            gcs.queue_frame(&hb);
        }
        gcs.flush();
        let mut buf = [0u8; 4096];
        let (a, _) = station.recv_from(&mut buf).unwrap();
        let (b, _) = station.recv_from(&mut buf).unwrap();
        assert_eq!(a + b, 80 * hb.len());
        assert!(a <= MAX_DATAGRAM && a % hb.len() == 0, "{a}");
        assert_eq!(gcs.counters().datagrams_out, 2);
    }
}
