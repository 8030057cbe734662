//! Seeds from software-in-the-loop captures: host-sim's SIL loop
//! ([`host_sim::harness::sil::fly`]) flies the firmware's pipeline against the rigid-body
//! plant with its noisy IMU, motion capture and ground-station frames in random chunks, and
//! [`Recorder`] writes down every call it makes as a [`crate::script`] operation. Replayed by
//! the pipeline target, a capture flies the same flight (up to the IMU's quantisation); its
//! link bytes alone are the decoder target's seeds.

use anyhow::{anyhow, Result};
use firmware::pipeline::ImuSample;
use host_sim::harness::sil::{
    self, FinalReport, FlightSoftware, InProcess, SilSetup, SilSummary, TickReport,
};

use crate::script::Op;
use crate::targets::pipeline;

/// Records the SIL loop's calls to the flight software as script operations, while flying them
/// on the SIL's own in-process pipeline at the script's clock (the loop needs its motor
/// outputs to go on).
pub struct Recorder {
    software: InProcess,
    /// The script's clock \[µs\] (the time of the last IMU sample or tick).
    now: u64,
    /// The operations so far.
    pub ops: Vec<Op>,
}

/// Telemetry room of every recorded tick \[B\] (the script's `Tick::room`).
const TELEMETRY_ROOM: u16 = 2047;

impl Recorder {
    /// A recorder flying `setup.flight`. Errors: the pipeline refuses it.
    pub fn new(setup: &SilSetup) -> Result<Self> {
        Ok(Self {
            software: InProcess::new(&setup.flight, usize::from(TELEMETRY_ROOM))?,
            now: 0,
            ops: Vec::new(),
        })
    }
}

/// An IMU sample as the script's quantised operation when it is 1 ms after the last and in
/// range, else as the `f32` one.
fn imu_op(sample: &ImuSample, dt: u64) -> Op {
    let q = |x: f32, scale: f32| {
        let v = (x * scale).round();
        (v.abs() < 32_000.0).then_some(v as i16)
    };
    let gyro = sample.gyro_rad_s.map(|x| q(x, 1e3));
    let accel = sample.accel_m_s2.map(|x| q(x, 1e2));
    if dt == 1000 && gyro.iter().chain(&accel).all(Option::is_some) {
        Op::ImuQuantised {
            gyro: gyro.map(|x| x.unwrap_or(0)),
            accel: accel.map(|x| x.unwrap_or(0)),
        }
    } else {
        Op::Imu {
            gyro: sample.gyro_rad_s,
            accel: sample.accel_m_s2,
            dt: dt.min(u64::from(u16::MAX)) as u16,
        }
    }
}

impl FlightSoftware for Recorder {
    fn on_link_bytes(&mut self, bytes: &[u8], _t_us: u64) -> Result<()> {
        for c in bytes.chunks(255) {
            self.ops.push(Op::Bytes(c.to_vec()));
        }
        // The script delivers bytes at its clock (the last sample's time): fly the same.
        self.software.on_link_bytes(bytes, self.now)
    }

    fn on_imu(&mut self, sample: &ImuSample) -> Result<()> {
        let dt = sample.time_us.saturating_sub(self.now);
        let op = imu_op(sample, dt);
        self.now += dt;
        let replayed = match &op {
            Op::ImuQuantised { gyro, accel } => ImuSample {
                gyro_rad_s: gyro.map(|x| f32::from(x) * 1e-3),
                accel_m_s2: accel.map(|x| f32::from(x) * 1e-2),
                time_us: self.now,
            },
            _ => ImuSample {
                time_us: self.now,
                ..*sample
            },
        };
        self.ops.push(op);
        self.software.on_imu(&replayed)
    }

    fn control_tick(&mut self, t_us: u64) -> Result<TickReport> {
        let dt = t_us.saturating_sub(self.now).min(u64::from(u16::MAX));
        self.now += dt;
        self.ops.push(Op::Tick {
            dt: dt as u16,
            room: TELEMETRY_ROOM,
        });
        let mut report = self.software.control_tick(self.now)?;
        // The loop dates the estimate on its own clock.
        report.estimate = report.estimate.map(|(_, p)| (t_us, p));
        Ok(report)
    }

    fn finish(&mut self) -> Result<FinalReport> {
        self.software.finish()
    }
}

/// A captured flight: its operations and what the pipeline did.
pub struct Capture {
    /// The script operations, in order.
    pub ops: Vec<Op>,
    /// The SIL loop's summary (events with their times, final state).
    pub summary: SilSummary,
}

/// Flies the SIL scenario `name` (`host-sim/scenarios/sil/`, seed `seed`) on the fuzzed
/// flight ([`pipeline::config`]: its short gyro calibration), held `hold_s` \[s\] and flown
/// `duration_s` \[s\] after the release, with `extra` ground-station messages (time after the
/// release \[s\], message), and records it.
///
/// Errors: unknown scenario, the pipeline refuses the flight, or the SIL loop fails.
pub fn record(
    name: &str,
    seed: u64,
    hold_s: f64,
    duration_s: f64,
    extra: &[(f64, firmware::link::mavlink::dialects::common::MavMessage)],
) -> Result<Capture> {
    let mut setup =
        sil::scenarios::by_name(name, seed).ok_or_else(|| anyhow!("no SIL scenario {name:?}"))?;
    setup.flight = pipeline::config();
    setup.hold_s = hold_s;
    setup.duration_s = duration_s;
    setup.commands.extend(extra.iter().cloned());
    // Outages are scripted for the full-length flights: keep them inside the window.
    setup.pose_outage = setup
        .pose_outage
        .map(|(a, b)| (a.min(duration_s / 2.0), b.min(duration_s)));
    let mut recorder = Recorder::new(&setup)?;
    let boot = recorder.software.pipeline().boot_report();
    let b = recorder
        .software
        .pipeline()
        .mixer()
        .effectiveness()
        .cast::<f64>();
    let summary = sil::fly(&setup, &boot, &b, &mut recorder, |_| {})?;
    Ok(Capture {
        ops: recorder.ops,
        summary,
    })
}
