//! `host-sim sil`: software in the loop.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use host_sim::harness::sil::{self, SilOptions};

/// Options of a software-in-the-loop run.
#[derive(Debug, Args, Clone)]
pub struct SilArgs {
    /// Scenario: `paper` (the helix from the upside-down start), `pose-loss` (failsafe),
    /// `takeoff-land` (host-sim/scenarios/sil/, embedded), or the path of a SIL scenario file.
    #[arg(long, default_value = "paper")]
    pub scenario: String,
    /// Random seed (sensor noise, dropouts, byte chunking).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// The control law's rate [Hz]: 100, 250, 500 or 1000. Default: the scenario's (its
    /// `control_rate_hz`, else the flight's: 100 Hz in the default build).
    #[arg(long, value_name = "HZ")]
    pub rate_hz: Option<f64>,
    /// Output directory. Default: `./out/sil-<scenario>`. Gets timeseries.csv and summary.json.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Attach a ground station on UDP (QGroundControl's default: 127.0.0.1:14550): the
    /// vehicle's telemetry goes there, its commands come back, the run is paced to the wall
    /// clock.
    #[arg(long, value_name = "ADDR")]
    pub gcs_udp: Option<std::net::SocketAddr>,
    /// Flight time after the hold [s] (default: the scenario's).
    #[arg(long, value_name = "S")]
    pub duration: Option<f64>,
}

/// Runs the SIL scenario ([`sil::run_command`]).
pub fn run(args: &SilArgs) -> Result<()> {
    sil::run_command(&SilOptions {
        scenario: args.scenario.clone(),
        seed: args.seed,
        rate_hz: args.rate_hz,
        out: args.out.clone(),
        gcs_udp: args.gcs_udp,
        duration_s: args.duration,
    })
}
