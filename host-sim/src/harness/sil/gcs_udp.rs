//! A ground station on UDP for software in the loop: QGroundControl, MAVProxy or a MAVROS
//! bridge talks to the in-process firmware pipeline as to a vehicle on a network link.
//!
//! The socket, the checks on what arrives and the pacing are shared with processor in the loop
//! ([`crate::harness::gcs_udp`]). Here, at each control tick, the run is paced to the wall clock
//! (so a person at the ground station sees the vehicle in real time), the datagrams that
//! arrived since the last tick go into the pipeline's link (whole frames, after the tick's
//! scenario bytes), and the tick's telemetry goes to the ground station as one datagram. The
//! scenario's own commands and poses still flow (motion capture is simulated) and are not
//! mirrored to the ground station; the vehicle's answers to them are part of its telemetry.

use anyhow::Result;

pub use crate::harness::gcs_udp::GcsUdp;

use super::{FinalReport, FlightSoftware, InProcess, TickReport};
use firmware::pipeline::ImuSample;

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
        use std::net::UdpSocket;
        use std::time::Duration;
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
        let c = software.gcs().counters();
        assert!(c.datagrams_in == 1 && c.frames_in == 1 && c.malformed == 0);
        assert!(c.datagrams_out > 10);
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
