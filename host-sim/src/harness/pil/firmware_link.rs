//! The firmware at the other end of the serial link, as the SIL loop's flight software: what
//! the host sends each step and how it rebuilds, from the firmware's telemetry, what SIL reads
//! from the pipeline's status (see the [module documentation](super) for the protocol).

use std::time::{Duration, Instant};

use anyhow::{bail, Result};
use firmware::config::FlightConfig;
use firmware::link;
use firmware::link::mavlink::dialects::common::{MavCmd, MavMessage, MavResult, MavState};
use firmware::pipeline::{ImuSample, Mode, MotorOutput};
use firmware::safety::FlightState;
use nalgebra::{Matrix4, Vector3, Vector4};

use super::chunking::{Chunker, SendChunking};
use super::frames::{self, Actuators, FrameReader, ReaderCounters, Target};
use super::transport::Transport;
use crate::harness::gcs_udp::GcsUdp;
use crate::harness::qemu::Received;
use crate::harness::sil::{FinalReport, FlightSoftware, TickReport};

/// The firmware at the other end of a [`Transport`], as the SIL loop's flight software: sends
/// the link bytes and one `HIL_SENSOR` per IMU sample, and at each tick reads the serial
/// output until the tick's `HIL_ACTUATOR_CONTROLS` and `POSITION_TARGET_LOCAL_NED`, rebuilding
/// what SIL reads from the pipeline's status (module documentation).
pub struct FirmwareLink<T: Transport> {
    transport: T,
    reader: FrameReader,
    timeout: Duration,
    rate_hz: u32,
    rotors: firmware::config::RotorConfig,
    effectiveness: Matrix4<f64>,
    pending: Vec<u8>,
    sequence: u8,
    bytes_sent: u64,
    state: FlightState,
    mode: Mode,
    reference: Vector3<f64>,
    estimate: Option<(u64, Vector3<f64>)>,
    events: Vec<(String, Option<FlightState>)>,
    refused: u32,
    ack_mode: Option<Mode>,
    last_frames: Vec<&'static str>,
    chunker: Chunker,
    /// `controls[k]` of `HIL_ACTUATOR_CONTROLS` is rotor `motor_slots[k]`'s throttle
    /// ([`FirmwareLink::with_motor_order`]).
    motor_slots: [usize; 4],
    /// Every frame taken in, raw, in order, when recording.
    received: Option<Vec<u8>>,
    /// A ground station on UDP ([`FirmwareLink::with_gcs`]).
    gcs: Option<GcsUdp>,
}

/// The reference mode of `HEARTBEAT.custom_mode` (the pipeline's `Mode as u32`).
pub fn mode_from_custom(custom_mode: u32) -> Option<Mode> {
    [
        Mode::Idle,
        Mode::Hover,
        Mode::Takeoff,
        Mode::Land,
        Mode::Helix,
        Mode::Mission,
    ]
    .into_iter()
    .find(|m| *m as u32 == custom_mode)
}

/// The flight state named at the start of a `STATUSTEXT` (`"failsafe: pose lost …"`) and the
/// rest of the text.
fn state_change(text: &str) -> Option<(FlightState, &str)> {
    let (name, reason) = text.split_once(": ")?;
    [
        FlightState::Disarmed,
        FlightState::Armed,
        FlightState::Failsafe,
    ]
    .into_iter()
    .find(|s| s.name() == name)
    .map(|s| (s, reason))
}

impl<T: Transport> FirmwareLink<T> {
    /// A link to the firmware flying `cfg` (its rotor curve turns throttles back into thrust;
    /// `effectiveness` is the mixer's matrix, rotor thrusts \[N\] → `(T [N], τ [N m])`), waiting
    /// at most `timeout` (wall clock) for each tick's answer.
    pub fn new(
        transport: T,
        cfg: &FlightConfig,
        effectiveness: Matrix4<f64>,
        timeout: Duration,
    ) -> Self {
        Self {
            transport,
            reader: FrameReader::new(),
            timeout,
            rate_hz: cfg.control_rate.hz(),
            rotors: cfg.rotors,
            effectiveness,
            pending: Vec::new(),
            sequence: 0,
            bytes_sent: 0,
            state: FlightState::Disarmed,
            mode: Mode::Idle,
            reference: Vector3::zeros(),
            estimate: None,
            events: Vec::new(),
            refused: 0,
            ack_mode: None,
            last_frames: Vec::new(),
            chunker: SendChunking::Whole.chunker(),
            motor_slots: [0, 1, 2, 3],
            received: None,
            gcs: None,
        }
    }

    /// The order the firmware sends its motor outputs in (its `FIRMWARE_HIL_MOTOR_ORDER`;
    /// default the vehicle file's): the throttles are put back in the mixer's order. Error: the
    /// rotors are not one per quadrant.
    pub fn with_motor_order(mut self, order: firmware::motor_order::MotorOrder) -> Result<Self> {
        self.motor_slots = order.slots(&self.rotors.rotors).map_err(|_| {
            anyhow::anyhow!("--motor-order {order:?}: the rotors are not one per quadrant")
        })?;
        Ok(self)
    }

    /// Cuts what is sent into writes as `chunking` says (default: one write per step).
    pub fn with_send_chunking(mut self, chunking: SendChunking) -> Self {
        self.chunker = chunking.chunker();
        self
    }

    /// Puts a ground station on UDP in front of the firmware's MAVLink link, as `host-sim sil
    /// --gcs-udp` does in front of the pipeline:
    /// - every 1 ms step, the datagrams that arrived and pass [`GcsUdp::poll`]'s check go to the
    ///   firmware as whole frames after the step's scenario bytes and before its `HIL_SENSOR`
    ///   (the firmware dates them by the `HIL_SENSOR` before, as the scenario's frames; the
    ///   stream stays a run of whole frames, so nothing the simulator sends is cut);
    /// - the firmware's frames, as the host reads them while it waits for each tick's answer,
    ///   go to the ground station, but for the two lockstep answers
    ///   ([`frames::goes_to_ground_station`]), raw (its sequence numbers and signatures kept), in
    ///   datagrams of whole frames sent at the end of each tick;
    /// - each tick waits for the wall clock to reach its simulated time ([`GcsUdp::pace`]): never
    ///   faster than real time. The emulator is usually slower, and then sets the pace.
    ///
    /// The lockstep is unchanged: the host still sends nothing more before the tick's answer.
    /// The simulator's own frames (poses, commands, `HIL_SENSOR`) are not mirrored to the ground
    /// station.
    pub fn with_gcs(mut self, gcs: GcsUdp) -> Self {
        self.gcs = Some(gcs);
        self
    }

    /// The ground station attached with [`Self::with_gcs`], for its counters.
    pub fn gcs(&self) -> Option<&GcsUdp> {
        self.gcs.as_ref()
    }

    /// Keeps every frame taken in from the firmware, raw, for [`Self::received`].
    pub fn recording(mut self) -> Self {
        self.received = Some(Vec::new());
        self
    }

    /// The frames taken in so far (raw MAVLink bytes, in order): every frame up to the one that
    /// completed the last tick answered, none after it (those race with the end of the run).
    /// `None` unless [`Self::recording`].
    pub fn received(&self) -> Option<&[u8]> {
        self.received.as_deref()
    }

    /// The transport back (to stop the emulator).
    pub fn into_transport(self) -> T {
        self.transport
    }

    /// Frame counters of the serial output read so far.
    pub fn serial_counters(&self) -> ReaderCounters {
        self.reader.counters()
    }

    /// Bytes sent so far.
    pub fn bytes_sent(&self) -> u64 {
        self.bytes_sent
    }

    fn flush(&mut self) -> Result<()> {
        let mut at = 0;
        while at < self.pending.len() {
            let (n, pause) = self.chunker.next_write(self.pending.len() - at);
            self.transport.send(&self.pending[at..at + n])?;
            at += n;
            if !pause.is_zero() {
                std::thread::sleep(pause);
            }
        }
        self.bytes_sent += self.pending.len() as u64;
        self.pending.clear();
        Ok(())
    }

    fn set_state(&mut self, to: FlightState, reason: &str) {
        if to != self.state {
            let from = self.state;
            self.state = to;
            self.events.push((
                format!("state {} -> {} ({reason})", from.name(), to.name()),
                Some(to),
            ));
        }
        if to == FlightState::Disarmed {
            self.set_mode(Mode::Idle);
        }
    }

    fn set_mode(&mut self, mode: Mode) {
        if mode != self.mode {
            self.mode = mode;
            self.events.push((format!("mode {}", mode.name()), None));
        }
    }

    /// Takes in one message of the firmware while waiting for tick `t_us`: `Some` actuators /
    /// `true` when the message is the tick's actuator frame / reference.
    fn take_in(
        &mut self,
        t_us: u64,
        message: MavMessage,
        actuators: &mut Option<Actuators>,
        target: &mut bool,
    ) -> Result<()> {
        if self.last_frames.len() == 8 {
            self.last_frames.remove(0);
        }
        self.last_frames
            .push(firmware::link::mavlink::Message::message_name(&message));
        match message {
            MavMessage::HIL_ACTUATOR_CONTROLS(m) => {
                let mut a = Actuators::from_message(&m);
                let sent = a.throttle;
                for (k, &rotor) in self.motor_slots.iter().enumerate() {
                    a.throttle[rotor] = sent[k];
                }
                if a.time_us != t_us {
                    bail!(
                        "PIL: HIL_ACTUATOR_CONTROLS for t = {} us while waiting for t = {t_us} us \
                         (the firmware ticked at another time: lockstep lost; was it built for \
                         the host's law rate of {} Hz? FIRMWARE_CONTROL_RATE_HZ, --rate-hz)",
                        a.time_us,
                        self.rate_hz
                    );
                }
                actuators.get_or_insert(a);
            }
            MavMessage::POSITION_TARGET_LOCAL_NED(m) => {
                let p = Target::from_message(&m);
                self.reference = p.position;
                *target |= u64::from(p.time_ms) * 1000 == t_us;
            }
            MavMessage::HEARTBEAT(m) => {
                let to = match m.system_status {
                    MavState::MAV_STATE_STANDBY => Some(FlightState::Disarmed),
                    MavState::MAV_STATE_ACTIVE => Some(FlightState::Armed),
                    MavState::MAV_STATE_CRITICAL => Some(FlightState::Failsafe),
                    _ => None,
                };
                if let Some(to) = to {
                    self.set_state(to, "HEARTBEAT");
                }
                if let Some(mode) = mode_from_custom(m.custom_mode) {
                    self.set_mode(mode);
                }
            }
            MavMessage::STATUSTEXT(m) => {
                let text = String::from_utf8_lossy(&m.text.to_str().map_or_else(
                    |_| m.text.iter().copied().take_while(|&b| b != 0).collect(),
                    |s| s.as_bytes().to_vec(),
                ))
                .into_owned();
                match state_change(&text) {
                    Some((to, reason)) => self.set_state(to, reason),
                    None => self.events.push((format!("text: {text}"), None)),
                }
            }
            MavMessage::COMMAND_ACK(m) => {
                self.events
                    .push((format!("ack {:?}: {:?}", m.command, m.result), None));
                if m.result != MavResult::MAV_RESULT_ACCEPTED {
                    self.refused += 1;
                } else if let Some(mode) = match m.command {
                    // An accepted mission, takeoff or landing switches the mode at once
                    // (taken after this tick's state changes); the next HEARTBEAT confirms it.
                    MavCmd::MAV_CMD_MISSION_START => Some(Mode::Helix),
                    MavCmd::MAV_CMD_NAV_TAKEOFF => Some(Mode::Takeoff),
                    MavCmd::MAV_CMD_NAV_LAND => Some(Mode::Land),
                    _ => None,
                } {
                    self.ack_mode = Some(mode);
                }
            }
            MavMessage::LOCAL_POSITION_NED(m) => {
                let p = firmware::frames::flip_vector([m.x, m.y, m.z]).cast::<f64>();
                self.estimate = Some((u64::from(m.time_boot_ms) * 1000, p));
            }
            _ => {}
        }
        Ok(())
    }

    fn report(&mut self, a: Actuators) -> TickReport {
        if let Some(mode) = self.ack_mode.take() {
            self.set_mode(mode);
        }
        let state = match (a.armed, self.state) {
            (false, _) => FlightState::Disarmed,
            (true, FlightState::Disarmed) => FlightState::Armed,
            (true, s) => s,
        };
        let mode = if state == FlightState::Disarmed {
            Mode::Idle
        } else {
            self.mode
        };
        let rotor = |u: f32| {
            if a.armed && u.is_finite() && u > 0.0 {
                f64::from(self.rotors.thrust_from_throttle(u))
            } else {
                0.0
            }
        };
        let wrench = self.effectiveness * Vector4::from(a.throttle.map(rotor));
        TickReport {
            output: MotorOutput {
                throttle: a.throttle,
                armed: a.armed,
            },
            state,
            mode,
            flying: mode != Mode::Idle,
            reference: self.reference,
            estimate: self.estimate,
            thrust: wrench[0],
            torque: [wrench[1], wrench[2], wrench[3]],
            events: std::mem::take(&mut self.events),
        }
    }
}

impl<T: Transport> FlightSoftware for FirmwareLink<T> {
    fn on_link_bytes(&mut self, bytes: &[u8], _t_us: u64) -> Result<()> {
        self.pending.extend_from_slice(bytes);
        Ok(())
    }

    fn on_imu(&mut self, sample: &ImuSample) -> Result<()> {
        let mut buf = [0u8; link::MAX_FRAME];
        let n = link::encode(
            &frames::hil_sensor(sample),
            255,
            190,
            self.sequence,
            &mut buf,
        );
        self.sequence = self.sequence.wrapping_add(1);
        if let Some(gcs) = self.gcs.as_mut() {
            // Here `pending` ends at a frame boundary (the loop hands over whole frames each
            // step), and so does each datagram that passes the check.
            gcs.poll(&mut self.pending)?;
        }
        self.pending.extend_from_slice(&buf[..n]);
        self.flush()
    }

    fn control_tick(&mut self, t_us: u64) -> Result<TickReport> {
        if let Some(gcs) = self.gcs.as_mut() {
            gcs.pace(t_us);
        }
        self.flush()?;
        let deadline = Instant::now() + self.timeout;
        let (mut actuators, mut target) = (None, false);
        loop {
            while let Some((_, message)) = self.reader.next_message() {
                if let Some(r) = self.received.as_mut() {
                    r.extend_from_slice(self.reader.last_frame());
                }
                if let Some(gcs) = self.gcs.as_mut() {
                    if frames::goes_to_ground_station(&message) {
                        gcs.queue_frame(self.reader.last_frame());
                    }
                }
                self.take_in(t_us, message, &mut actuators, &mut target)?;
                if let (Some(a), true) = (actuators, target) {
                    if let Some(gcs) = self.gcs.as_mut() {
                        gcs.flush();
                    }
                    return Ok(self.report(a));
                }
            }
            let left = deadline.saturating_duration_since(Instant::now());
            match self.transport.receive(left) {
                Received::Bytes(b) => self.reader.push(&b),
                Received::Timeout => bail!(
                    "PIL stall at t = {t_us} us: no {} within {:.1} s (wall clock); last frames \
                     from the firmware: {:?}; {} B sent, {:?} read, {} B held after the last \
                     frame: {:02x?}; {}",
                    match (actuators.is_some(), target) {
                        (false, false) =>
                            "HIL_ACTUATOR_CONTROLS and POSITION_TARGET_LOCAL_NED for this tick",
                        (false, true) => "HIL_ACTUATOR_CONTROLS for this tick",
                        _ => "POSITION_TARGET_LOCAL_NED for this tick",
                    },
                    self.timeout.as_secs_f64(),
                    self.last_frames,
                    self.bytes_sent,
                    self.reader.counters(),
                    self.reader.pending_bytes().len(),
                    self.reader.pending_bytes(),
                    self.transport.post_mortem()
                ),
                Received::Closed => bail!(
                    "PIL: the firmware's serial output closed at t = {t_us} us (emulator \
                     exited: crash, panic or hard fault?); last frames: {:?}; {}",
                    self.last_frames,
                    self.transport.post_mortem()
                ),
            }
        }
    }

    fn finish(&mut self) -> Result<FinalReport> {
        let c = self.reader.counters();
        Ok(FinalReport {
            mixer_saturations: 0,
            link_frames: [0; 3],
            telemetry_frames: [c.valid, c.malformed],
            state: self.state,
            non_finite: 0,
            refused_commands: self.refused,
        })
    }
}
