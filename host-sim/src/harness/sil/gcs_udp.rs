//! A ground station on UDP for software in the loop: QGroundControl, MAVProxy or a MAVROS
//! bridge talks to the in-process firmware pipeline as to a vehicle on a network link.
//!
//! The vehicle's telemetry goes to the ground station's address (default 127.0.0.1:14550, where
//! QGroundControl listens and `mavproxy.py --master udpin:0.0.0.0:14550` too) from an ephemeral
//! port; whatever arrives on that port goes into the pipeline's link before the next control
//! tick, and the last sender becomes the peer. The simulation is paced to the wall clock, so a
//! person at the ground station sees the vehicle in real time. The scenario's own commands and
//! poses still flow (motion capture is simulated).

use std::net::{SocketAddr, UdpSocket};
use std::time::{Duration, Instant};

use anyhow::{Context, Result};

use super::{FinalReport, FlightSoftware, InProcess, TickReport};
use firmware::pipeline::ImuSample;

/// The UDP end of the link, and the pacing.
pub struct GcsUdp {
    socket: UdpSocket,
    peer: SocketAddr,
    started: Option<Instant>,
    realtime: bool,
    /// Datagrams received from, and sent to, the ground station.
    pub datagrams: [u64; 2],
}

impl GcsUdp {
    /// A socket on an ephemeral local port sending to `peer`; `realtime`: pace the run to the
    /// wall clock. Errors: the socket cannot be opened.
    pub fn open(peer: SocketAddr, realtime: bool) -> Result<Self> {
        let local: SocketAddr = if peer.is_ipv4() {
            ([0, 0, 0, 0], 0).into()
        } else {
            (std::net::Ipv6Addr::UNSPECIFIED, 0).into()
        };
        let socket = UdpSocket::bind(local).context("cannot open the ground-station UDP socket")?;
        socket.set_nonblocking(true)?;
        Ok(Self {
            socket,
            peer,
            started: None,
            realtime,
            datagrams: [0, 0],
        })
    }

    /// The local address the ground station answers to.
    pub fn local_addr(&self) -> Result<SocketAddr> {
        Ok(self.socket.local_addr()?)
    }

    /// Appends every datagram waiting to `into`; the last sender becomes the peer. Errors:
    /// socket failures other than "nothing waiting" (and ICMP port-unreachable answers to our
    /// sends, which mean only that no ground station listens yet, are ignored).
    fn poll(&mut self, into: &mut Vec<u8>) -> Result<()> {
        let mut buf = [0u8; 2048];
        loop {
            match self.socket.recv_from(&mut buf) {
                Ok((n, from)) => {
                    into.extend_from_slice(&buf[..n]);
                    self.peer = from;
                    self.datagrams[0] += 1;
                }
                Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => return Ok(()),
                Err(e) if e.kind() == std::io::ErrorKind::ConnectionRefused => {}
                Err(e) => return Err(e).context("ground-station UDP receive failed"),
            }
        }
    }

    fn send(&mut self, bytes: &[u8]) {
        // A ground station that is not there yet is not an error: the datagram is lost.
        if !bytes.is_empty() && self.socket.send_to(bytes, self.peer).is_ok() {
            self.datagrams[1] += 1;
        }
    }

    fn pace(&mut self, t_us: u64) {
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

/// The in-process pipeline with a UDP ground station attached ([`GcsUdp`]).
pub struct WithGcs {
    inner: InProcess,
    gcs: GcsUdp,
    incoming: Vec<u8>,
}

impl WithGcs {
    /// `inner` with `gcs` attached.
    pub fn new(inner: InProcess, gcs: GcsUdp) -> Self {
        Self {
            inner,
            gcs,
            incoming: Vec::new(),
        }
    }

    /// The ground-station end (for its counters).
    pub fn gcs(&self) -> &GcsUdp {
        &self.gcs
    }
}

impl FlightSoftware for WithGcs {
    fn on_link_bytes(&mut self, bytes: &[u8], t_us: u64) -> Result<()> {
        self.inner.on_link_bytes(bytes, t_us)
    }

    fn on_imu(&mut self, sample: &ImuSample) -> Result<()> {
        self.inner.on_imu(sample)
    }

    fn control_tick(&mut self, t_us: u64) -> Result<TickReport> {
        self.gcs.pace(t_us);
        self.incoming.clear();
        self.gcs.poll(&mut self.incoming)?;
        if !self.incoming.is_empty() {
            self.inner.on_link_bytes(&self.incoming, t_us)?;
        }
        let report = self.inner.control_tick(t_us)?;
        self.gcs.send(self.inner.last_telemetry());
        Ok(report)
    }

    fn finish(&mut self) -> Result<FinalReport> {
        self.inner.finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::harness::sil::scenarios;
    use firmware::link::mavlink::dialects::common::{MavCmd, MavMessage, COMMAND_LONG_DATA};
    use firmware::link::{self, Decoder};

    /// Given a SIL run with a UDP ground station (a socket on localhost), when the ground
    /// station asks for AUTOPILOT_VERSION, then it receives the vehicle's telemetry (heartbeats)
    /// and the COMMAND_ACK to its request, addressed to it.
    #[test]
    fn a_ground_station_on_udp_talks_to_the_pipeline() {
        let station = UdpSocket::bind("127.0.0.1:0").unwrap();
        station
            .set_read_timeout(Some(Duration::from_millis(200)))
            .unwrap();
        let mut setup = scenarios::load("takeoff-land", 1).unwrap();
        setup.duration_s = 1.0;
        setup.hold_s = 0.5;
        let gcs = GcsUdp::open(station.local_addr().unwrap(), false).unwrap();
        let vehicle = gcs.local_addr().unwrap();
        let request = MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
            param1: 148.0,
            command: MavCmd::MAV_CMD_REQUEST_MESSAGE,
            target_system: 1,
            ..Default::default()
        });
        let mut frame = [0u8; link::MAX_FRAME];
        let n = link::encode(&request, 255, 190, 0, &mut frame);
        // Waiting in the socket before the first tick.
        station
            .send_to(&frame[..n], ("127.0.0.1", vehicle.port()))
            .unwrap();
        let inner = InProcess::new(&setup.flight, 1024).unwrap();
        let boot = inner.pipeline().boot_report();
        let b = inner.pipeline().mixer().effectiveness().cast::<f64>();
        let mut software = WithGcs::new(inner, gcs);
        super::super::fly(&setup, &boot, &b, &mut software, |_| {}).unwrap();
        assert!(software.gcs().datagrams[0] == 1 && software.gcs().datagrams[1] > 10);
        let mut names = Vec::new();
        let mut d = Decoder::new(255);
        let mut buf = [0u8; 4096];
        while let Ok(n) = station.recv(&mut buf) {
            // The ground station's decoder drops the vehicle's frames as "not for a vehicle";
            // count them by id instead.
            let mut i = 0;
            while i + 12 <= n {
                let len = usize::from(buf[i + 1]);
                names.push(u32::from_le_bytes([buf[i + 7], buf[i + 8], buf[i + 9], 0]));
                i += 12 + len;
            }
            d.push(&buf[..n], |_| {});
        }
        assert_eq!(d.counters().frames_malformed, 0);
        assert!(names.contains(&0), "heartbeat");
        assert!(names.contains(&148), "AUTOPILOT_VERSION");
        assert!(names.contains(&77), "COMMAND_ACK");
    }
}
