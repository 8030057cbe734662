//! Software in the loop: the firmware's flight pipeline (`firmware::pipeline`, the code that
//! flies on the STM32) against the rigid-body plant, with simulated sensors and actuators.
//!
//! - IMU at 1 kHz with noise and bias ([`sensors::ImuModel`]);
//! - motion capture at 100 Hz with noise, latency and dropouts, each pose a real MAVLink 2
//!   frame from the firmware's encoder, delivered in random chunks to the firmware's decoder
//!   ([`sensors::MocapModel`]);
//! - ground-station commands as MAVLink frames too;
//! - motors: throttle → thrust through the vehicle's curve, first-order lag on rotor speed
//!   (the flight's airframe's motor time constant unless the scenario sets one), per-rotor
//!   limits;
//!   the plant ([`crate::model::plant`]) is driven by the four rotor thrusts through the mixer's
//!   effectiveness matrix (the same geometry the firmware allocates with);
//! - optionally a flat ground (contact stops the body) for takeoff and landing.
//!
//! [`scenarios`] defines the runs (files in the format of [`scenario_file`]); [`run`] executes one and returns its records and summary.
//! The loop itself ([`fly`]) only sees the flight software through [`FlightSoftware`]: the
//! in-process pipeline here, the firmware under QEMU in [`crate::harness::pil`].

mod flight;
pub use flight::fly;
mod command;
mod extremes;
pub mod gcs_udp;
mod record;
pub mod scenario_file;
pub mod scenarios;
pub mod sensors;
mod setup;

pub use command::{record_run, run_command, SilOptions};
pub use extremes::FlightExtremes;
pub use record::{human_summary, SilRecord, SilSummary};
pub use setup::SilSetup;

use std::collections::VecDeque;

use anyhow::{anyhow, Result};
use firmware::config::FlightConfig;
use firmware::link::mavlink::dialects::common::MavMessage;
use firmware::link::{self, Decoder};
use firmware::pipeline::{Event, FlightPipeline, ImuSample, Mode, MotorOutput};
use firmware::safety::FlightState;
use nalgebra::Vector3;

use sensors::Rng;

/// Motors: throttle → commanded thrust through the vehicle's curve (0 when stopped), then a
/// first-order lag on rotor *speed* (thrust ∝ speed², as RotorPy's and PX4's Gazebo motor
/// models): with `s = √f`, `ṡ = (√f_cmd − s)/τ_m`, stepped exactly over each plant substep;
/// per-rotor limits.
#[derive(Clone, Copy, Debug)]
struct Motors {
    thrust: [f64; 4],
}

impl Motors {
    fn step(&mut self, cfg: &FlightConfig, out: &MotorOutput, h: f64, tau: f64) {
        let r = &cfg.rotors;
        let alpha = 1.0 - (-h / tau).exp();
        for k in 0..4 {
            let u = out.throttle[k];
            let target = if out.armed && u.is_finite() && u > 0.0 {
                f64::from(r.thrust_from_throttle(u))
            } else {
                0.0
            };
            let speed = self.thrust[k].max(0.0).sqrt();
            let speed = speed + (target.max(0.0).sqrt() - speed) * alpha;
            self.thrust[k] = (speed * speed).clamp(0.0, f64::from(r.thrust_max));
        }
    }
}

/// A byte chunk due at a time.
struct Delivery {
    at_us: u64,
    bytes: Vec<u8>,
    /// The last chunk of a pose frame.
    pose_end: bool,
}

fn schedule(queue: &mut VecDeque<Delivery>, at_us: u64, frame: &[u8], rng: &mut Rng, pose: bool) {
    // Random chunking: the UART DMA hands over arbitrary pieces.
    let mut i = 0;
    while i < frame.len() {
        let n = 1 + (rng.next_u64() % 40) as usize;
        let j = (i + n).min(frame.len());
        queue.push_back(Delivery {
            at_us,
            bytes: frame[i..j].to_vec(),
            pose_end: pose && j == frame.len(),
        });
        i = j;
    }
}

fn encode(m: &MavMessage, seq: &mut u8) -> Vec<u8> {
    let mut buf = [0u8; link::MAX_FRAME];
    let n = link::encode(m, 255, 190, *seq, &mut buf);
    *seq = seq.wrapping_add(1);
    buf[..n].to_vec()
}

fn describe(e: &Event) -> String {
    match e {
        Event::StateChanged { from, to, reason } => {
            format!("state {} -> {} ({reason})", from.name(), to.name())
        }
        Event::ModeChanged { mode } => format!("mode {}", mode.name()),
        Event::MissionItemReached { seq } => format!("mission item {seq} reached"),
        other => format!("{other:?}"),
    }
}

/// What the flight software reported for one control tick, in the simulation's terms.
#[derive(Clone, Debug, PartialEq)]
pub struct TickReport {
    /// The motor commands of the tick (throttles in mixer order, whether armed).
    pub output: MotorOutput,
    /// Flight state after the tick.
    pub state: FlightState,
    /// Reference mode after the tick.
    pub mode: Mode,
    /// Whether the controller tracks the reference, so the position error counts.
    pub flying: bool,
    /// Reference position \[m\], NWU.
    pub reference: Vector3<f64>,
    /// Latest position estimate: (its time \[µs\], position \[m\] NWU), `None` if none is known.
    /// The loop compares it with the true position at that time (the last 64 ticks are kept).
    pub estimate: Option<(u64, Vector3<f64>)>,
    /// Allocated collective thrust \[N\].
    pub thrust: f64,
    /// Allocated torque [N m], body FLU.
    pub torque: [f64; 3],
    /// What happened since the last tick, oldest first: a description for the summary and,
    /// for a flight-state change, the new state.
    pub events: Vec<(String, Option<FlightState>)>,
}

/// Counters of the flight software at the end of a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FinalReport {
    /// Control ticks in which the mixer gave something up.
    pub mixer_saturations: u32,
    /// Link frames the flight software accepted / dropped / found malformed.
    pub link_frames: [u32; 3],
    /// Telemetry frames it sent that decode (CRC-valid) / that do not.
    pub telemetry_frames: [u32; 2],
    /// Final flight state.
    pub state: FlightState,
    /// Non-finite values counted.
    pub non_finite: u32,
    /// Commands and setpoints refused.
    pub refused_commands: u32,
}

/// The flight software under test as the simulation loop ([`fly`]) drives it, on the SIL
/// clock (µs from the start of the run, 1 ms steps). Per step the loop calls
/// [`on_link_bytes`](Self::on_link_bytes) for the link bytes due (ground station, motion
/// capture; MAVLink 2 from system 255), then [`on_imu`](Self::on_imu) if an IMU sample is due,
/// then [`control_tick`](Self::control_tick) at every control period.
///
/// Implementations: the in-process [`FlightPipeline`] (SIL, [`run`]) and the firmware under
/// QEMU over its serial port (processor in the loop, [`crate::harness::pil`]).
pub trait FlightSoftware {
    /// Link bytes arriving at `t_us` \[µs\] (any chunking). Errors: transport failures.
    fn on_link_bytes(&mut self, bytes: &[u8], t_us: u64) -> Result<()>;
    /// One IMU sample (body FLU, time-stamped on the SIL clock). Errors: transport failures.
    fn on_imu(&mut self, sample: &ImuSample) -> Result<()>;
    /// The control tick at `t_us` \[µs\]: the motor commands and what the software reports.
    /// Errors: the software crashed, stalled or answered for another time.
    fn control_tick(&mut self, t_us: u64) -> Result<TickReport>;
    /// Counters at the end of the run. Errors: as [`control_tick`](Self::control_tick).
    fn finish(&mut self) -> Result<FinalReport>;
}

/// The firmware's pipeline in process (SIL): bytes and samples straight into its calls, its
/// telemetry decoded back by a ground-station decoder (counted), its `status()` as the report.
pub struct InProcess {
    pipeline: FlightPipeline,
    gcs: Decoder,
    telemetry: Vec<u8>,
    telemetry_len: usize,
}

impl InProcess {
    /// The pipeline of `flight`, writing up to `telemetry_room` bytes \[B\] of telemetry per
    /// control tick. Errors: the pipeline refuses the configuration (`FlightPipeline::new`).
    pub fn new(flight: &FlightConfig, telemetry_room: usize) -> Result<Self> {
        let pipeline = FlightPipeline::new(flight)
            .map_err(|e| anyhow!("flight pipeline refused the set-up: {e:?}"))?;
        Ok(Self {
            pipeline,
            gcs: Decoder::new(255),
            telemetry: vec![0u8; telemetry_room],
            telemetry_len: 0,
        })
    }

    /// The telemetry bytes of the last control tick.
    pub fn last_telemetry(&self) -> &[u8] {
        &self.telemetry[..self.telemetry_len]
    }

    /// The pipeline flown (for its boot report and mixer before the flight).
    pub fn pipeline(&self) -> &FlightPipeline {
        &self.pipeline
    }
}

impl FlightSoftware for InProcess {
    fn on_link_bytes(&mut self, bytes: &[u8], t_us: u64) -> Result<()> {
        self.pipeline.on_link_bytes(bytes, t_us);
        Ok(())
    }

    fn on_imu(&mut self, sample: &ImuSample) -> Result<()> {
        self.pipeline.on_imu(sample);
        Ok(())
    }

    fn control_tick(&mut self, t_us: u64) -> Result<TickReport> {
        let output = self.pipeline.control_tick(t_us);
        let n = self.pipeline.telemetry(t_us, &mut self.telemetry);
        self.telemetry_len = n;
        self.gcs.push(&self.telemetry[..n], |_| {});
        let mut events = Vec::new();
        while let Some(e) = self.pipeline.take_events() {
            let to = match e {
                Event::StateChanged { to, .. } => Some(to),
                _ => None,
            };
            events.push((describe(&e), to));
        }
        let st = self.pipeline.status();
        Ok(TickReport {
            output,
            state: st.state,
            mode: st.mode,
            flying: st.position_error > 0.0 || st.mode != Mode::Idle,
            reference: Vector3::from(st.reference_position).cast::<f64>(),
            estimate: Some((t_us, Vector3::from(st.position).cast::<f64>())),
            thrust: f64::from(st.thrust),
            torque: st.torque.map(f64::from),
            events,
        })
    }

    fn finish(&mut self) -> Result<FinalReport> {
        let st = self.pipeline.status();
        let l = st.counters.link;
        let g = self.gcs.counters();
        Ok(FinalReport {
            mixer_saturations: st.counters.mixer_saturations,
            link_frames: [l.frames_ok, l.frames_dropped, l.frames_malformed],
            // The vehicle's telemetry is not vehicle-bound input: the GCS-side decoder counts
            // its CRC-valid frames as "dropped" (not used) and bad ones as malformed.
            telemetry_frames: [g.frames_ok + g.frames_dropped, g.frames_malformed],
            state: st.state,
            non_finite: st.counters.non_finite,
            refused_commands: st.counters.refused_commands,
        })
    }
}

/// Runs `setup`, calling `observe` for every control tick.
///
/// Errors: the configuration is refused by the pipeline (`FlightPipeline::new`).
pub fn run(setup: &SilSetup, observe: impl FnMut(&SilRecord)) -> Result<SilSummary> {
    let mut software = InProcess::new(&setup.flight, 1024)?;
    let boot = software.pipeline.boot_report();
    let b = software.pipeline.mixer().effectiveness().cast::<f64>();
    fly(setup, &boot, &b, &mut software, observe)
}
