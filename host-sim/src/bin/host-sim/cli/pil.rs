//! `host-sim pil`: processor in the loop.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use host_sim::harness::pil::{self, PilCommandOptions};

/// Options of a processor-in-the-loop run (the SIL `paper` scenario on the firmware in QEMU).
#[derive(Debug, Args, Clone)]
pub struct PilArgs {
    /// Firmware ELF for QEMU `mps2-an386`. Default:
    /// `$CARGO_TARGET_DIR` (or `<workspace>/target`) + `/thumbv7em-none-eabihf/release/firmware-mps2-an386`.
    #[arg(long, value_name = "PATH")]
    pub elf: Option<PathBuf>,
    /// QEMU binary.
    #[arg(long, value_name = "BIN", default_value = "qemu-system-arm")]
    pub qemu: PathBuf,
    /// Output directory. Default: `./out/pil`. Gets timeseries.csv, summary.json, defmt.bin
    /// and defmt.log (and telemetry.bin with --record-telemetry).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Random seed (sensor noise, dropouts, byte chunking).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Flight time after release, in seconds. Default: the scenario's 30 s.
    #[arg(long, value_name = "S")]
    pub duration: Option<f64>,
    /// The control law's rate [Hz] the firmware was built with (`FIRMWARE_CONTROL_RATE_HZ` or
    /// its flight file's `[design] control_rate_hz`): 100, 250, 500 or 1000. The host ticks
    /// the lockstep at this rate; a mismatch stops the run ("lockstep lost").
    #[arg(long, value_name = "HZ", default_value_t = 100.0)]
    pub rate_hz: f64,
    /// Stall timeout: wall-clock seconds to wait for the firmware's answer to a tick.
    #[arg(long, value_name = "S", default_value_t = pil::DEFAULT_TIMEOUT_S)]
    pub timeout: f64,
    /// How the bytes sent to the firmware are cut into writes: `whole` (one per 1 ms step),
    /// `bytes` (one per byte), `random` (sizes 1 to 96, a 5 ms pause after one write in four,
    /// drawn from seed 1) or `random:<seed>`. The firmware's lockstep must not depend on it
    /// (docs/sil-pil.md).
    #[arg(long, value_name = "HOW", default_value = "whole")]
    pub send_chunking: pil::SendChunking,
    /// The order of the firmware's motor outputs in HIL_ACTUATOR_CONTROLS, as it was built
    /// (`FIRMWARE_HIL_MOTOR_ORDER`): `mixer` (the vehicle file's), `px4` or `betaflight`.
    #[arg(long, value_name = "ORDER", default_value = "mixer", value_parser = parse_motor_order)]
    pub motor_order: firmware::motor_order::MotorOrder,
    /// Also write telemetry.bin: every MAVLink frame taken in from the firmware, raw, up to
    /// the last tick's answer (compare two runs with `cmp`).
    #[arg(long)]
    pub record_telemetry: bool,
    /// Attach a ground station on UDP (QGroundControl's default: 127.0.0.1:14550), as `sil
    /// --gcs-udp`: the firmware's telemetry goes there from an ephemeral port (printed), the
    /// frames sent to that port go to the firmware between the simulator's frames, and the
    /// run goes at most at real time (QEMU is usually slower). The lockstep is kept.
    #[arg(long, value_name = "ADDR")]
    pub gcs_udp: Option<std::net::SocketAddr>,
}

/// Runs the PIL flight ([`pil::run_command`]).
pub fn run(args: &PilArgs) -> Result<()> {
    pil::run_command(&PilCommandOptions {
        elf: args.elf.clone(),
        qemu: args.qemu.clone(),
        out: args.out.clone(),
        seed: args.seed,
        duration: args.duration,
        rate_hz: args.rate_hz,
        timeout: args.timeout,
        send_chunking: args.send_chunking,
        motor_order: args.motor_order,
        record_telemetry: args.record_telemetry,
        gcs_udp: args.gcs_udp,
    })
}

fn parse_motor_order(s: &str) -> Result<firmware::motor_order::MotorOrder, String> {
    firmware::motor_order::MotorOrder::parse(s)
        .ok_or_else(|| format!("`{s}`: expected mixer, px4 or betaflight"))
}
