//! The law-rate study (`host-sim rates`): what running the law at 100, 250, 500 or 1 000 Hz
//! buys against motor lag, measured two ways at every rate of
//! [`firmware::control_rate::ControlRate::ALL`]:
//!
//! - software in the loop ([`sil_rows`]): the firmware's pipeline (the build's vehicle and
//!   certified gains) with its IMU and motion capture over MAVLink, rotors with first-order
//!   speed lag, in the SIL scenarios `helix` (tracking from an upright start) and `paper`
//!   (released upside down);
//! - a campaign ([`campaign_rows`]): the paper's law in `f32` on the rotor plant (the firmware's
//!   mixer, four rotors with motor lag) of a vehicle file, from Haar-random and 180° starts.
//!
//! Each gives tracking error, torque peaks and the margins left to the certificate's a-priori
//! bounds; [`run_command`] writes them to `rates.md` (tables) and `rates.json`.

pub mod campaign_rows;
pub mod sil_rows;
mod table;

use std::path::PathBuf;

use anyhow::{Context, Result};
use firmware::control_rate::ControlRate;
use serde::Serialize;

pub use campaign_rows::{CampaignPlan, CampaignRow};
pub use sil_rows::SilRow;

/// The SIL scenarios of the study.
pub const SIL_SCENARIOS: [&str; 2] = ["helix", "paper"];

/// What `host-sim rates` runs.
#[derive(Clone, Debug, PartialEq)]
pub struct RateStudyOptions {
    /// Output directory (created; files overwritten).
    pub out: PathBuf,
    /// Seed of the SIL runs (sensor noise, dropouts, byte chunking).
    pub sil_seed: u64,
    /// The campaign at every rate; `None`: SIL only.
    pub campaign: Option<CampaignPlan>,
}

/// Everything the study measured (`rates.json`).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct RateStudy {
    /// SIL rows, by scenario then rate.
    pub sil: Vec<SilRow>,
    /// Campaign rows, by rate (empty without a campaign).
    pub campaign: Vec<CampaignRow>,
    /// The campaign's vehicle file and motor time constant override \[s\], if one ran.
    pub campaign_vehicle: Option<(String, Option<f64>)>,
    /// Runs per rate of the campaign (0 without one).
    pub campaign_runs: u64,
}

/// Runs the study. Errors: a run is refused (scenario, vehicle file, configuration).
pub fn run(options: &RateStudyOptions) -> Result<RateStudy> {
    let mut sil = Vec::new();
    for name in SIL_SCENARIOS {
        for rate in ControlRate::ALL {
            let row = sil_rows::fly(name, options.sil_seed, f64::from(rate.hz()))
                .with_context(|| format!("SIL {name} at {} Hz", rate.hz()))?;
            eprintln!("SIL {name} at {} Hz done", rate.hz());
            sil.push(row);
        }
    }
    let mut campaign = Vec::new();
    if let Some(plan) = &options.campaign {
        for rate in ControlRate::ALL {
            let row = campaign_rows::fly(plan, rate.hz())
                .with_context(|| format!("campaign at {} Hz", rate.hz()))?;
            eprintln!("campaign at {} Hz done", rate.hz());
            campaign.push(row);
        }
    }
    Ok(RateStudy {
        sil,
        campaign,
        campaign_vehicle: options
            .campaign
            .as_ref()
            .map(|p| (p.vehicle.display().to_string(), p.motor_time_constant_s)),
        campaign_runs: options.campaign.as_ref().map_or(0, |p| p.runs),
    })
}

/// `host-sim rates`: runs the study, prints the tables, writes `rates.md` and `rates.json`.
///
/// Errors: as [`run`]; a file cannot be written.
pub fn run_command(options: &RateStudyOptions) -> Result<()> {
    let study = run(options)?;
    let text = table::markdown(&study);
    print!("{text}");
    std::fs::create_dir_all(&options.out)?;
    let md = options.out.join("rates.md");
    let json = options.out.join("rates.json");
    std::fs::write(&md, &text).with_context(|| format!("writing {}", md.display()))?;
    std::fs::write(&json, serde_json::to_string_pretty(&study)?)
        .with_context(|| format!("writing {}", json.display()))?;
    println!("Wrote {} and {}", md.display(), json.display());
    Ok(())
}
