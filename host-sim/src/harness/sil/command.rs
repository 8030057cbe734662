//! The `sil` subcommand: one SIL scenario run from the command line (or paced to the wall clock
//! with a ground station on UDP), its records written to `timeseries.csv` and its summary to
//! `summary.json`.

use anyhow::{anyhow, Result};
use serde::Serialize;

use super::{fly, gcs_udp, human_summary, run, scenarios, InProcess, SilRecord};

/// What the `sil` subcommand runs.
#[derive(Clone, Debug, PartialEq)]
pub struct SilOptions {
    /// Scenario: a name of [`super::scenarios::NAMES`] (the command line's default: `paper`) or the path
    /// of a SIL scenario file (format: [`super::scenario_file`]).
    pub scenario: String,
    /// Random seed (sensor noise, dropouts, byte chunking); the command line's default: 1.
    pub seed: u64,
    /// The law's rate \[Hz\] (100, 250, 500 or 1000; `None`: the scenario's).
    pub rate_hz: Option<f64>,
    /// Output directory (`None`: `./out/sil-<scenario>`); gets timeseries.csv and summary.json.
    pub out: Option<std::path::PathBuf>,
    /// A ground station on UDP at this address ([`gcs_udp`]): telemetry to it, its frames into
    /// the link, the run paced to the wall clock.
    pub gcs_udp: Option<std::net::SocketAddr>,
    /// Flight time after the hold \[s\] (`None`: the scenario's), e.g. long enough to fly it
    /// from a ground station.
    pub duration_s: Option<f64>,
}

/// The `sil` subcommand: runs the scenario, prints the summary, writes `timeseries.csv` and
/// `summary.json`. Errors: unknown scenario name or a bad scenario file (with file, key and
/// reason); an unsupported rate; the run failed or a file could not be written.
pub fn run_command(args: &SilOptions) -> Result<()> {
    let mut setup = scenarios::load(&args.scenario, args.seed)?;
    if let Some(hz) = args.rate_hz {
        setup
            .set_control_rate_hz(hz)
            .map_err(|e| anyhow!("--rate-hz: {e}"))?;
    }
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| std::path::PathBuf::from("out").join(format!("sil-{}", setup.name)));
    if let Some(d) = args.duration_s {
        anyhow::ensure!(
            d.is_finite() && d > 0.0,
            "--duration must be a positive number of seconds, not {d}"
        );
        setup.duration_s = d;
    }
    let (summary, [csv_path, json_path]) = match args.gcs_udp {
        None => record_run(&out, |observe| run(&setup, observe))?,
        Some(peer) => record_run(&out, |observe| {
            let inner = InProcess::new(&setup.flight, 1024)?;
            let boot = inner.pipeline().boot_report();
            let b = inner.pipeline().mixer().effectiveness().cast::<f64>();
            let gcs = gcs_udp::GcsUdp::open(peer, true)?;
            println!(
                "ground station: telemetry to {peer} from {}, paced to the wall clock",
                gcs.local_addr()?
            );
            let mut software = gcs_udp::WithGcs::new(inner, gcs);
            let flight = fly(&setup, &boot, &b, &mut software, observe);
            println!("{}", software.gcs().summary());
            flight
        })?,
    };
    print!("{}", human_summary(&summary));
    println!("Wrote {} and {}", csv_path.display(), json_path.display());
    Ok(())
}

/// Runs `fly_one` with an observer that writes every record to `out/timeseries.csv`, then
/// writes the summary it returns to `out/summary.json` (creating `out`; files overwritten).
/// Returns the summary and the two paths. Errors: `fly_one`'s, or the files cannot be written
/// (the CSV holds the records so far when `fly_one` fails).
pub fn record_run<S: Serialize>(
    out: &std::path::Path,
    fly_one: impl FnOnce(&mut dyn FnMut(&SilRecord)) -> Result<S>,
) -> Result<(S, [std::path::PathBuf; 2])> {
    std::fs::create_dir_all(out)?;
    let csv_path = out.join("timeseries.csv");
    let mut writer = csv::Writer::from_path(&csv_path)?;
    let mut write_error = None;
    let summary = fly_one(&mut |r| {
        if write_error.is_none() {
            if let Err(e) = writer.serialize(r) {
                write_error = Some(e);
            }
        }
    })?;
    if let Some(e) = write_error {
        return Err(e.into());
    }
    writer.flush()?;
    let json_path = out.join("summary.json");
    std::fs::write(&json_path, serde_json::to_string_pretty(&summary)?)?;
    Ok((summary, [csv_path, json_path]))
}
