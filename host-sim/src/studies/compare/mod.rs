//! `host-sim compare`: the paper's law against the baselines on the same runs, as a markdown
//! report with tables and embedded plots (`compare.md`), plus `compare.json`.
//!
//! Contestants: the paper's law (controller-core, the scenario's precision), Lee et al. (2010)
//! unclipped and with the commands clipped to the physical limits, and the PX4-style cascade
//! (which clips its own outputs). Every contestant flies the same initial conditions and the same
//! noise draws (seeds derive from the campaign seed and the run index only).
//!
//! Sections: the baselines' own sanity checks (hover, 1 m step); the seven 180° starts; a
//! campaign (Haar attitudes, offsets in balls); chattering under attitude noise at 180°.

mod plots;
use plots::write_plots;
mod markdown;
pub use markdown::markdown;
pub mod sanity;
pub use sanity::{helix_tracking_error, sanity, SanityRow};
use std::path::PathBuf;

use anyhow::{Context, Result};
use rayon::prelude::*;
use serde::Serialize;

use crate::fly::controllers::ControllerKind;
use crate::model::scenario::Scenario;
use crate::runs::metrics::BoundSet;
use crate::runs::runner::{bound_set, run_one, RunResult};
use crate::runs::sampler::{run_seed, Sampler, SamplerRadii, HALF_TURN_AXES};
use crate::runs::stats::{summarise, CampaignStats};
use crate::studies::ablation::integral::convergence_of;
use crate::studies::campaign::options::BaseOptions;
use crate::studies::campaign::{run_campaign, CampaignConfig};

/// One contestant: a controller, whether the plant clips its commands, and whether the
/// paper's law flies the scenario's bounded integral action.
#[derive(Clone, Debug, Serialize)]
pub struct Contestant {
    /// Report label.
    pub label: String,
    /// Controller.
    pub controller: ControllerKind,
    /// Commands clipped to the physical limits before the plant.
    pub clip: bool,
    /// The scenario's `[gains.integral]` is kept (`false`: removed, so the law, its thrust cap
    /// and its bounds are the paper's). Only the paper's law reads it.
    pub integral: bool,
}

impl Contestant {
    /// The scenario this contestant flies: `base` with its clipping and, without the integral
    /// action, `[gains.integral]` removed.
    pub fn scenario(&self, base: &Scenario) -> Scenario {
        let mut s = base.clone();
        s.simulation.clip_to_limits = self.clip;
        if !self.integral {
            s.gains.integral = None;
        }
        s
    }
}

/// The contestants for a base scenario: the paper's law (with and without the bounded integral
/// action when the scenario has one, docs/integral-action.md), Lee et al. unclipped and clipped,
/// and the PX4-style cascade.
pub fn contestants(scenario: &Scenario) -> Vec<Contestant> {
    let clip = scenario.simulation.clip_to_limits;
    let c = |label: &str, controller, clip, integral| Contestant {
        label: label.into(),
        controller,
        clip,
        integral,
    };
    let mut list = Vec::new();
    if scenario.gains.integral.is_some() {
        list.push(c("paper + integral", ControllerKind::Paper, clip, true));
    }
    list.extend([
        c("paper", ControllerKind::Paper, clip, false),
        c("lee", ControllerKind::Lee, clip, false),
        c("lee (clipped)", ControllerKind::Lee, true, false),
        c("px4", ControllerKind::Px4, clip, false),
    ]);
    list
}

/// One contestant's results.
#[derive(Clone, Debug, Serialize)]
pub struct ContestantResult {
    /// Contestant.
    pub contestant: Contestant,
    /// Sanity checks.
    pub sanity: SanityRow,
    /// The seven 180° starts (10 m ball).
    pub half_turns: CampaignStats,
    /// The campaign.
    pub campaign: CampaignStats,
    /// Chattering runs: 180° starts at the reference with attitude noise.
    pub chattering: CampaignStats,
    /// The bounds this contestant's samples are checked against: the extended certificate's
    /// with the integral action, the paper's without (the report's `bounds` otherwise).
    pub bounds: BoundSet,
}

/// `compare.json`.
#[derive(Clone, Debug, Serialize)]
pub struct CompareReport {
    /// Campaign runs per contestant.
    pub runs: u64,
    /// Seed.
    pub seed: u64,
    /// Attitude noise of the chattering runs \[deg\].
    pub chattering_noise_deg: f64,
    /// The plant every contestant flies (with `"rotors"`, every controller's `(T, τ)` goes
    /// through the firmware's mixer and the rotors).
    pub plant: crate::model::scenario::PlantKind,
    /// Definitions.
    pub definitions: String,
    /// Bounds and limits.
    pub bounds: BoundSet,
    /// Results per contestant.
    pub results: Vec<ContestantResult>,
}

/// Attitude noise of the chattering comparison [deg per axis].
pub const CHATTER_NOISE_DEG: f64 = 2.0;

fn chattering(
    base: &Scenario,
    c: &Contestant,
    seed: u64,
    bounds: BoundSet,
) -> Result<CampaignStats> {
    let mut s = c.scenario(base);
    s.perturbations.attitude_noise_std_rad = CHATTER_NOISE_DEG.to_radians();
    let radii = SamplerRadii {
        position_m: 0.0,
        velocity_m_s: 0.0,
        angular_velocity_rad_s: 0.0,
    };
    let sampler = Sampler::new(&s, radii)?;
    let axes = HALF_TURN_AXES.len() as u64;
    let results: Vec<RunResult> = (0..2 * axes)
        .into_par_iter()
        .map(|i| {
            let seed = run_seed(seed, i);
            let initial = sampler.sample(i % axes, seed, true);
            run_one(
                &s,
                c.controller,
                i,
                seed,
                &initial,
                convergence_of(base),
                bounds,
            )
        })
        .collect();
    Ok(summarise(&results, true))
}

/// Runs the whole comparison; also returns each contestant's campaign settling times. Runs are
/// judged as `campaign` judges them, 5 s before the end of the scenario's runs
/// ([`convergence_of`]: 25 s into the paper's 30 s).
///
/// Errors: invalid scenario, or a sanity run the controller refused.
pub fn run_compare(
    base: &Scenario,
    runs: u64,
    seed: u64,
) -> Result<(CompareReport, Vec<Vec<RunResult>>)> {
    let bounds = bound_set(base)?;
    let mut results = Vec::new();
    let mut campaigns = Vec::new();
    for c in contestants(base) {
        let s = c.scenario(base);
        // Without the integral action the law's bounds are the paper's, not the extended ones.
        let own_bounds = if c.integral || base.gains.integral.is_none() {
            bounds
        } else {
            bound_set(&s)?
        };
        let config = |runs, radii| CampaignConfig {
            scenario: s.clone(),
            controller: c.controller,
            runs,
            seed,
            radii,
            half_turns: true,
            convergence: convergence_of(base),
            progress: true,
            threads: None,
        };
        let nominal = !s.perturbations.violates_model();
        let half = run_campaign(&config(
            HALF_TURN_AXES.len() as u64,
            SamplerRadii::default(),
        ))?;
        let campaign = run_campaign(&config(runs, SamplerRadii::default()))?;
        results.push(ContestantResult {
            sanity: SanityRow {
                helix_tracking_error_m: Some(
                    helix_tracking_error(base, &c, own_bounds)
                        .with_context(|| format!("helix run of {}", c.label))?,
                ),
                ..sanity(base, &c, own_bounds)
                    .with_context(|| format!("sanity runs of {}", c.label))?
            },
            half_turns: summarise(&half, nominal),
            campaign: summarise(&campaign, nominal),
            chattering: chattering(base, &c, seed, own_bounds)?,
            bounds: own_bounds,
            contestant: c,
        });
        campaigns.push(campaign);
    }
    Ok((
        CompareReport {
            runs,
            seed,
            chattering_noise_deg: CHATTER_NOISE_DEG,
            plant: base.simulation.plant,
            definitions: convergence_of(base).describe(),
            bounds,
            results,
        },
        campaigns,
    ))
}

/// What the `compare` job runs (the command line's defaults in parentheses).
#[derive(Clone, Debug, PartialEq)]
pub struct CompareOptions {
    /// Output directory, created; files overwritten (`out/compare`).
    pub out: PathBuf,
    /// Runs of the campaign each controller flies, the same initial conditions for all (200).
    pub runs: u64,
    /// Scenario, seed and overrides.
    pub base: BaseOptions,
}

/// `host-sim compare`: runs the comparison and writes `compare.md`, `compare.json`, plots.
///
/// Errors: invalid scenario, a failed sanity run, or a file that cannot be written.
pub fn run_command(args: &CompareOptions) -> Result<()> {
    let base = args.base.scenario()?;
    let (report, campaigns) = run_compare(&base, args.runs, args.base.seed)?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let plots = write_plots(&args.out, &base, &report, &campaigns)?;
    let md = markdown(&report, &plots);
    let md_path = args.out.join("compare.md");
    std::fs::write(&md_path, &md).with_context(|| format!("writing {}", md_path.display()))?;
    let json_path = args.out.join("compare.json");
    std::fs::write(&json_path, serde_json::to_string_pretty(&report)? + "\n")
        .with_context(|| format!("writing {}", json_path.display()))?;
    print!("{md}");
    println!(
        "Wrote compare.md, compare.json and {} plots to {}",
        plots.len(),
        args.out.display()
    );
    Ok(())
}
