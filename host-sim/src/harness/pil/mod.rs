//! Processor in the loop: the firmware, compiled for Cortex-M4F, runs in QEMU (`mps2-an386`)
//! and flies the SIL plant, sensors and scenarios ([`crate::harness::sil`]) over its serial port, in
//! lockstep with the simulation clock.
//!
//! Protocol (MAVLink 2; host = system 255 / component 190, firmware = 1 / 1), for every 1 ms
//! step `t` \[µs\] of the SIL clock (from 0):
//! 1. the link bytes due at `t` (ground-station `COMMAND_LONG`s, motion-capture poses), exactly
//!    the SIL frames;
//! 2. one `HIL_SENSOR` (#107) with the IMU sample ([`frames::hil_sensor`]: FLU → FRD).
//!
//! The firmware ticks when it has a `HIL_SENSOR` with `time_usec` ≥ its next deadline (0, then
//! one law period later each time: 10 ms at the default 100 Hz, 1 ms at 1 kHz), i.e. at
//! `t` = 0, 10 000, 20 000 µs… at 100 Hz, and answers with `HIL_ACTUATOR_CONTROLS`
//! (#93: `time_usec` = `t`, throttles in `controls[0..4]`, `mode` `SAFETY_ARMED` when armed)
//! and `POSITION_TARGET_LOCAL_NED` (#85: `time_boot_ms` = `t`/1000, the reference, NED), plus
//! its usual telemetry. At each tick the host blocks until it has both for `t` (wall-clock
//! timeout, default 20 s), then applies the throttles to the SIL motors until the next tick.
//! The host ticks at the setup's rate ([`PilCommandOptions::rate_hz`]), which must be the one
//! the firmware was built with (`FIRMWARE_CONTROL_RATE_HZ`); otherwise the first answer for
//! another time stops the run.
//! So the run is deterministic whatever the emulator's speed.
//!
//! Differences from SIL:
//! - The firmware dates each message by the last `HIL_SENSOR` before it in the stream
//!   (`firmware::pipeline::lockstep`), so a pose sent at `t` (before that step's `HIL_SENSOR`)
//!   is stamped `t − 1 ms` (SIL: `t`), and the estimator, which takes a pose to be 10 ms old on
//!   arrival, dates it 1 ms too early. How the bytes are cut into writes
//!   ([`PilOptions::send_chunking`]) changes nothing the firmware does.
//! - The pipeline's `status()` is not available; the records are rebuilt from the telemetry:
//!   state from `STATUSTEXT` (`"<state>: <reason>"`, every state change) and `HEARTBEAT`
//!   (`system_status`; 1 Hz), the motors' armed flag from the actuator frame; mode from
//!   the `COMMAND_ACK` of an accepted mission start, takeoff or landing and from
//!   `HEARTBEAT.custom_mode` (1 Hz: a mode change without a command, e.g. the end of a
//!   landing, shows up to 1 s late, and the position error counts from then); reference from
//!   `POSITION_TARGET_LOCAL_NED`; the estimate from `LOCAL_POSITION_NED` (20 Hz; its error is
//!   against the true position at its time);
//!   thrust and torque from the throttles through the rotor curve and the mixer's
//!   effectiveness matrix (so at idle they are the idle rotors' wrench, where SIL reports 0).
//!   Telemetry the firmware sends after the actuator frame of a tick is read with the next
//!   tick (events one law period later than SIL's).
//! - The firmware's counters (link frames, mixer saturations, non-finite values, refusals)
//!   come from its last 1 Hz defmt counter lines ([`defmt_log::counters`]): up to 1 s old at
//!   the end of the run.
//!
//! With a ground station on UDP ([`PilOptions::gcs_udp`], `host-sim pil --gcs-udp ADDR`), its
//! checked frames join the stream at whole-frame boundaries before each step's `HIL_SENSOR`,
//! and the firmware's frames but the two lockstep answers go to it
//! ([`FirmwareLink::with_gcs`]); the run is then also held to at most real time. Without one,
//! the bytes sent and the run are exactly as described above.
//!
//! [`run`] spawns QEMU ([`crate::harness::qemu`]), flies a scenario through
//! [`crate::harness::sil::fly`], kills QEMU and decodes its defmt log ([`defmt_log`]);
//! [`run_command`] is the `pil` subcommand.

pub mod chunking;
pub mod defmt_log;
pub mod firmware_link;
pub mod frames;
pub mod transport;

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{bail, Context, Result};
use firmware::pipeline::FlightPipeline;
use serde::Serialize;

use crate::harness::gcs_udp::{GcsSummary, GcsUdp};
use crate::harness::qemu::Qemu;
use crate::harness::sil::{self, SilRecord, SilSetup, SilSummary};
pub use chunking::SendChunking;
use defmt_log::FirmwareCounters;
pub use firmware::motor_order::MotorOrder;
use firmware_link::FirmwareLink;
use frames::ReaderCounters;

/// The firmware binary QEMU runs, relative to the target directory.
pub const ELF_IN_TARGET_DIR: &str = "thumbv7em-none-eabihf/release/firmware-mps2-an386";

/// Default stall timeout: wall-clock time to wait for a tick's answer \[s\].
pub const DEFAULT_TIMEOUT_S: f64 = 20.0;

/// The default firmware ELF: `$CARGO_TARGET_DIR/` (relative to the current directory, as cargo
/// reads it) or `<workspace>/target/`, then [`ELF_IN_TARGET_DIR`]. Built by
/// `cargo build -p firmware --target thumbv7em-none-eabihf --release --no-default-features
/// --features board-mps2-an386`.
pub fn default_elf() -> PathBuf {
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            Path::new(env!("CARGO_MANIFEST_DIR"))
                .parent()
                .unwrap_or(Path::new("."))
                .join("target")
        });
    target.join(ELF_IN_TARGET_DIR)
}

/// How to run the emulator.
#[derive(Clone, Debug, PartialEq)]
pub struct PilOptions {
    /// The firmware ELF (`mps2-an386` board build).
    pub elf: PathBuf,
    /// The QEMU binary (`qemu-system-arm`).
    pub qemu: PathBuf,
    /// Output directory: QEMU writes `defmt.bin` there, [`run`] adds `defmt.log`.
    pub out: PathBuf,
    /// Wall-clock time to wait for each tick's answer before declaring a stall.
    pub timeout: Duration,
    /// How the bytes sent to the firmware are cut into writes (default: one write per step).
    pub send_chunking: SendChunking,
    /// The order of the firmware's motor outputs (its `FIRMWARE_HIL_MOTOR_ORDER`).
    pub motor_order: firmware::motor_order::MotorOrder,
    /// Write `telemetry.bin` to `out`: every MAVLink frame taken in from the firmware, raw, in
    /// order, up to the last tick's answer ([`FirmwareLink::received`]).
    pub record_telemetry: bool,
    /// A ground station on UDP at this address (`None`: none, the run as without this
    /// option): [`FirmwareLink::with_gcs`], paced to at most real time.
    pub gcs_udp: Option<std::net::SocketAddr>,
}

/// The file [`run`] writes the received telemetry to, in [`PilOptions::out`], when
/// [`PilOptions::record_telemetry`].
pub const TELEMETRY_FILE: &str = "telemetry.bin";

/// What a processor-in-the-loop run showed.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct PilSummary {
    /// The flight, as SIL reports it (see the module documentation for the fields rebuilt from
    /// telemetry or the defmt log).
    #[serde(flatten)]
    pub flight: SilSummary,
    /// The firmware ELF flown.
    pub elf: String,
    /// Wall-clock time of the flight (QEMU start to the last tick) \[s\].
    pub wall_time_s: f64,
    /// Simulated time flown (hold + duration) \[s\].
    pub simulated_s: f64,
    /// QEMU's exit status: normally killed by the host at the end (e.g. `signal: 9 (SIGKILL)`);
    /// an exit code means the firmware ended the emulation itself.
    pub qemu_exit: String,
    /// MAVLink frames read from the firmware's serial port: valid, malformed (must be 0),
    /// bytes outside frames.
    pub serial: ReaderCounters,
    /// Bytes sent to the firmware's serial port.
    pub bytes_sent: u64,
    /// How they were cut into writes (`whole`, `bytes`, `random:<seed>`).
    pub send_chunking: String,
    /// The firmware's counters from its last 1 Hz defmt lines (`None`: not in the log); the
    /// flight's `link_frames`, `mixer_saturated_ticks`, `non_finite` and `refused_commands`
    /// come from here (else they hold 0 / the refused `COMMAND_ACK`s).
    pub firmware_counters: Option<FirmwareCounters>,
    /// Control-step overruns since boot from the firmware's last 1 Hz `timing:` line
    /// ([`defmt_log::overruns`]; `None`: not in the log).
    pub firmware_overruns: Option<u32>,
    /// The longest control step \[µs\] in the firmware's `timing:` lines
    /// ([`defmt_log::longest_step_us`]; `None`: not in the log).
    pub firmware_longest_step_us: Option<u32>,
    /// Lines of the decoded defmt log.
    pub defmt_lines: usize,
    /// defmt frames that did not decode.
    pub defmt_malformed: usize,
    /// Why the defmt log could not be decoded (`None`: decoded).
    pub defmt_error: Option<String>,
    /// The boot certificate line of the log (`certificate: …`, ending in the verdict
    /// `certificate holds` or `certificate FAILS`), if present.
    pub certificate_line: Option<String>,
    /// The boot banner's rotor-fit line (`mixer fit: certified set margin …`, ending in the
    /// verdict `set fits`, `set fits WITHOUT the required margin` or `set does NOT fit`), if
    /// present.
    pub box_line: Option<String>,
    /// The boot banner's vehicle line (`flight: vehicle <name> (<source>)`), if present.
    pub vehicle_line: Option<String>,
    /// The ground-station link's counters (`None`, and absent from summary.json: no
    /// [`PilOptions::gcs_udp`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gcs: Option<GcsSummary>,
}

/// Flies `setup` on the firmware in QEMU (`options`), calling `observe` for every tick, then
/// stops QEMU and writes `defmt.log` (decoded) next to `defmt.bin` in `options.out`.
///
/// Errors: the IMU is not at 1 kHz (the lockstep needs a `HIL_SENSOR` every step), the ELF is
/// missing, QEMU cannot start, the configuration is refused, or the firmware stalled, crashed
/// (the message has QEMU's exit status and the tail of the defmt log) or lost the lockstep.
pub fn run(
    setup: &SilSetup,
    options: &PilOptions,
    observe: impl FnMut(&SilRecord),
) -> Result<PilSummary> {
    if (setup.imu.rate_hz - 1000.0).abs() > 1e-9 {
        bail!(
            "PIL needs the IMU at 1 kHz (one HIL_SENSOR per 1 ms step), not {} Hz",
            setup.imu.rate_hz
        );
    }
    if !options.elf.is_file() {
        bail!(
            "firmware ELF not found at {}: build it with `cargo build -p firmware --target \
             thumbv7em-none-eabihf --release --no-default-features --features \
             board-mps2-an386`, or pass --elf",
            options.elf.display()
        );
    }
    let pipeline = FlightPipeline::new(&setup.flight)
        .map_err(|e| anyhow::anyhow!("flight pipeline refused the set-up: {e:?}"))?;
    let boot = pipeline.boot_report();
    let b = pipeline.mixer().effectiveness().cast::<f64>();
    // Before QEMU starts, so that a bad address stops the run with nothing to clean up.
    let gcs = match options.gcs_udp {
        Some(peer) => {
            let gcs = GcsUdp::open(peer, true)?;
            println!(
                "ground station: telemetry to {peer} from {}; frames to that port go to the \
                 firmware; at most real time",
                gcs.local_addr()?
            );
            Some(gcs)
        }
        None => None,
    };
    std::fs::create_dir_all(&options.out)?;
    let bin = options.out.join("defmt.bin");
    let log_path = options.out.join("defmt.log");

    let start = Instant::now();
    let mut qemu = Qemu::spawn_serial_link(&options.qemu, &options.elf, &bin)?;
    let elf = options.elf.clone();
    qemu.set_log_decoder(move |bin| match defmt_log::decode_files(&elf, bin) {
        Ok(log) => log.lines,
        Err(e) => vec![format!("(defmt log not decoded: {e:#})")],
    });
    let mut firmware = FirmwareLink::new(qemu, &setup.flight, b, options.timeout)
        .with_send_chunking(options.send_chunking)
        .with_motor_order(options.motor_order)?;
    if options.record_telemetry {
        firmware = firmware.recording();
    }
    if let Some(gcs) = gcs {
        firmware = firmware.with_gcs(gcs);
    }
    let flight = sil::fly(setup, &boot, &b, &mut firmware, observe);
    let wall_time_s = start.elapsed().as_secs_f64();
    let gcs = firmware.gcs().map(GcsUdp::summary);
    if let Some(received) = firmware.received() {
        let path = options.out.join(TELEMETRY_FILE);
        std::fs::write(&path, received).with_context(|| format!("writing {}", path.display()))?;
    }
    let serial = firmware.serial_counters();
    let bytes_sent = firmware.bytes_sent();
    let mut qemu = firmware.into_transport();
    let exit = qemu.stop();
    drop(qemu);

    let decoded = defmt_log::decode_files(&options.elf, &bin);
    if let Ok(log) = &decoded {
        let mut text = log.lines.join("\n");
        text.push('\n');
        std::fs::write(&log_path, text)
            .with_context(|| format!("writing {}", log_path.display()))?;
    }
    let mut flight = flight?;
    let (lines, malformed, defmt_error) = match &decoded {
        Ok(log) => (log.lines.as_slice(), log.malformed, None),
        Err(e) => (&[][..], 0, Some(format!("{e:#}"))),
    };
    let firmware_counters = defmt_log::counters(lines);
    let firmware_overruns = defmt_log::overruns(lines);
    let firmware_longest_step_us = defmt_log::longest_step_us(lines);
    if let Some(c) = firmware_counters {
        flight.link_frames = c.link_frames;
        flight.mixer_saturated_ticks = c.mixer_saturated;
        flight.non_finite = c.non_finite;
        flight.refused_commands = c.refused;
    }
    Ok(PilSummary {
        flight,
        elf: options.elf.display().to_string(),
        wall_time_s,
        simulated_s: setup.hold_s + setup.duration_s,
        qemu_exit: exit.map_or_else(|| "unknown".into(), |s| s.to_string()),
        serial,
        bytes_sent,
        send_chunking: options.send_chunking.to_string(),
        firmware_counters,
        firmware_overruns,
        firmware_longest_step_us,
        defmt_lines: lines.len(),
        defmt_malformed: malformed,
        defmt_error,
        certificate_line: lines.iter().find(|l| l.contains("certificate:")).cloned(),
        box_line: lines
            .iter()
            .find(|l| l.contains("mixer fit: certified set margin"))
            .cloned(),
        vehicle_line: lines
            .iter()
            .find(|l| l.contains("flight: vehicle"))
            .cloned(),
        gcs,
    })
}

/// A short human summary.
pub fn human_summary(s: &PilSummary) -> String {
    use std::fmt::Write;
    let mut o = String::new();
    let _ = writeln!(
        o,
        "PIL scenario {} (seed {}) on QEMU mps2-an386: {}",
        s.flight.scenario, s.flight.seed, s.elf
    );
    let _ = writeln!(
        o,
        "  {:.1} s simulated in {:.1} s wall clock ({:.2}x real time); {} B sent (writes: {}); serial \
         frames valid {} malformed {}, {} B outside frames; QEMU {}",
        s.simulated_s,
        s.wall_time_s,
        s.simulated_s / s.wall_time_s,
        s.bytes_sent,
        s.send_chunking,
        s.serial.valid,
        s.serial.malformed,
        s.serial.discarded,
        s.qemu_exit
    );
    // The flight as SIL prints it, without its title line.
    for line in sil::human_summary(&s.flight).lines().skip(1) {
        let _ = writeln!(o, "{line}");
    }
    let _ = writeln!(
        o,
        "  defmt log: {} lines, {} malformed{}; {}",
        s.defmt_lines,
        s.defmt_malformed,
        s.defmt_error
            .as_ref()
            .map_or_else(String::new, |e| format!(" (not decoded: {e})")),
        s.certificate_line
            .as_deref()
            .unwrap_or("no certificate line")
    );
    let _ = writeln!(
        o,
        "  {}; {}",
        s.vehicle_line.as_deref().unwrap_or("no vehicle line"),
        s.box_line.as_deref().unwrap_or("no box-fit line")
    );
    let _ = writeln!(
        o,
        "  control-step overruns: {}; longest step: {}",
        s.firmware_overruns.map_or_else(
            || "unknown (no `timing:` line)".to_string(),
            |n| n.to_string()
        ),
        s.firmware_longest_step_us
            .map_or_else(|| "unknown".to_string(), |n| format!("{n} us"))
    );
    if let Some(gcs) = &s.gcs {
        let _ = writeln!(o, "  {gcs}");
    }
    if s.firmware_counters.is_none() {
        let _ = writeln!(
            o,
            "  (no `link:`/`pipeline:` counter lines in the defmt log: firmware counters unknown)"
        );
    }
    o
}

/// What the `pil` subcommand runs: the SIL `paper` scenario on the firmware in QEMU.
#[derive(Clone, Debug, PartialEq)]
pub struct PilCommandOptions {
    /// Firmware ELF for QEMU `mps2-an386` (`None`: [`default_elf`]).
    pub elf: Option<PathBuf>,
    /// QEMU binary (the command line's default: `qemu-system-arm`).
    pub qemu: PathBuf,
    /// Output directory (`None`: `./out/pil`); gets timeseries.csv, summary.json, defmt.bin
    /// and defmt.log.
    pub out: Option<PathBuf>,
    /// Random seed (sensor noise, dropouts, byte chunking); the command line's default: 1.
    pub seed: u64,
    /// Flight time after release \[s\], finite and ≥ 0 (`None`: the scenario's 30 s).
    pub duration: Option<f64>,
    /// The law's rate \[Hz\] the firmware ELF was built with (100, 250, 500 or 1000): the
    /// host ticks the lockstep at it.
    pub rate_hz: f64,
    /// Stall timeout: wall-clock seconds to wait for the firmware's answer to a tick, finite
    /// and > 0 (the command line's default: [`DEFAULT_TIMEOUT_S`]).
    pub timeout: f64,
    /// How the bytes sent are cut into writes (the command line's default: one per step).
    pub send_chunking: SendChunking,
    /// The order of the firmware's motor outputs (the command line's default: the vehicle
    /// file's).
    pub motor_order: firmware::motor_order::MotorOrder,
    /// Also write [`TELEMETRY_FILE`] (the firmware's frames, raw) to the output directory.
    pub record_telemetry: bool,
    /// A ground station on UDP at this address ([`PilOptions::gcs_udp`]; `None`: none).
    pub gcs_udp: Option<std::net::SocketAddr>,
}

/// The `pil` subcommand: the paper scenario (SIL's `scenarios::paper`) on the firmware in
/// QEMU; writes `timeseries.csv`, `summary.json`, `defmt.bin` and `defmt.log` to the output
/// directory and prints a summary. Errors (non-zero exit): the run failed (missing ELF or
/// QEMU, stall, crash, lockstep lost) or a file could not be written; the convergence itself
/// is judged by the tests.
pub fn run_command(args: &PilCommandOptions) -> Result<()> {
    let mut setup = sil::scenarios::paper(args.seed);
    setup
        .set_control_rate_hz(args.rate_hz)
        .map_err(|e| anyhow::anyhow!("--rate-hz: {e}"))?;
    if let Some(d) = args.duration {
        if !(d.is_finite() && d >= 0.0) {
            bail!("--duration must be a finite number of seconds >= 0, not {d}");
        }
        setup.duration_s = d;
    }
    if !(args.timeout.is_finite() && args.timeout > 0.0) {
        bail!(
            "--timeout must be a positive number of seconds, not {}",
            args.timeout
        );
    }
    let options = PilOptions {
        elf: args.elf.clone().unwrap_or_else(default_elf),
        qemu: args.qemu.clone(),
        out: args
            .out
            .clone()
            .unwrap_or_else(|| PathBuf::from("out").join("pil")),
        timeout: Duration::from_secs_f64(args.timeout),
        send_chunking: args.send_chunking,
        motor_order: args.motor_order,
        record_telemetry: args.record_telemetry,
        gcs_udp: args.gcs_udp,
    };
    let (summary, [csv, json]) =
        sil::record_run(&options.out, |observe| run(&setup, &options, observe))?;
    print!("{}", human_summary(&summary));
    println!(
        "Wrote {}, {}, {} and {}",
        csv.display(),
        json.display(),
        options.out.join("defmt.bin").display(),
        options.out.join("defmt.log").display()
    );
    if options.record_telemetry {
        println!("Wrote {}", options.out.join(TELEMETRY_FILE).display());
    }
    Ok(())
}

#[cfg(test)]
mod fake;
