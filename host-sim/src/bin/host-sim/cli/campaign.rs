//! `host-sim campaign`: a robustness campaign, whole or one shard of it, and `campaign merge`,
//! which combines the shards.

use std::path::PathBuf;

use anyhow::Result;
use clap::{Args, Subcommand, ValueEnum};
use host_sim::fly::controllers::ControllerKind;
use host_sim::studies::campaign::{self, CampaignOptions, Convergence, SamplerRadii, Shard};

use super::common::BaseArgs;

/// Which controller a run uses (the command line's spelling of [`ControllerKind`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ControllerArg {
    /// The paper's saturated hybrid law (controller-core), at the scenario's precision.
    Paper,
    /// Lee, Leok, McClamroch (2010) geometric SE(3) controller.
    Lee,
    /// PX4-style cascade.
    Px4,
    /// Ablation: the paper's law with the memoryless `q₀ ≥ 0` lifting (no hysteresis, no memory);
    /// always f64.
    PaperMemoryless,
    /// Ablation: the paper's law without the two output filters; always f64.
    PaperNoFilter,
}

impl From<ControllerArg> for ControllerKind {
    fn from(c: ControllerArg) -> Self {
        match c {
            ControllerArg::Paper => ControllerKind::Paper,
            ControllerArg::Lee => ControllerKind::Lee,
            ControllerArg::Px4 => ControllerKind::Px4,
            ControllerArg::PaperMemoryless => ControllerKind::PaperMemoryless,
            ControllerArg::PaperNoFilter => ControllerKind::PaperNoFilter,
        }
    }
}

/// Options of `host-sim campaign`.
#[derive(Debug, Args, Clone)]
#[command(args_conflicts_with_subcommands = true)]
pub struct CampaignArgs {
    /// `merge`: combine shards (no campaign options then).
    #[command(subcommand)]
    pub action: Option<CampaignAction>,
    /// Number of runs.
    #[arg(long, default_value_t = 1000)]
    pub runs: u64,
    /// Output directory (created; files overwritten).
    #[arg(long, value_name = "DIR", default_value = "out/campaign")]
    pub out: PathBuf,
    /// Controller flown in every run.
    #[arg(long, value_enum, default_value_t = ControllerArg::Paper)]
    pub controller: ControllerArg,
    /// Scenario, seed and overrides.
    #[command(flatten)]
    pub base: BaseArgs,
    /// Radius of the position-offset ball around p_d(0) (m).
    #[arg(long, default_value_t = SamplerRadii::default().position_m)]
    pub position_radius_m: f64,
    /// Radius of the velocity-offset ball around the reference velocity [m/s].
    #[arg(long, default_value_t = SamplerRadii::default().velocity_m_s)]
    pub velocity_radius_m_s: f64,
    /// Radius of the body angular-velocity ball [rad/s].
    #[arg(long, default_value_t = SamplerRadii::default().angular_velocity_rad_s)]
    pub angular_velocity_radius_rad_s: f64,
    /// Leave out the fixed 180° starts (all runs Haar-uniform).
    #[arg(long)]
    pub no_half_turns: bool,
    /// Convergence: position error threshold (m).
    #[arg(long, default_value_t = Convergence::default().position_m)]
    pub converged_position_m: f64,
    /// Convergence: attitude error threshold (deg).
    #[arg(long, default_value_t = Convergence::default().attitude_deg)]
    pub converged_attitude_deg: f64,
    /// Convergence: settled by this time (s) [default: 5 s before the end of the run, 25 s for
    /// the paper's 30 s]
    #[arg(long)]
    pub converged_after_s: Option<f64>,
    /// Write only campaign.json and runs.csv.
    #[arg(long)]
    pub no_plots: bool,
    /// Worker threads (default: one per core); the results do not depend on it.
    #[arg(long)]
    pub threads: Option<usize>,
    /// Run only shard K of N (0 <= K < N: runs floor(K*runs/N) up to floor((K+1)*runs/N)) and
    /// write its partial result, OUT/shard.json, instead of the campaign's files; combine the N
    /// shards with `campaign merge`. Give every shard the same options.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<Shard>,
}

/// Subcommands of `host-sim campaign`.
#[derive(Debug, Subcommand, Clone)]
pub enum CampaignAction {
    /// Combine the shards of one campaign (`campaign --shard K/N`, N of them) into the
    /// campaign.json, runs.csv and plots a single run would write; refuses shards of
    /// different campaigns, of different splits, given twice or missing.
    Merge(MergeArgs),
}

/// Options of `host-sim campaign merge`.
#[derive(Debug, Args, Clone)]
pub struct MergeArgs {
    /// The shards' output directories, each holding one shard.json (any order).
    #[arg(required = true, value_name = "DIR")]
    pub dirs: Vec<PathBuf>,
    /// Output directory (created; files overwritten).
    #[arg(long, value_name = "DIR", default_value = "out/campaign")]
    pub out: PathBuf,
    /// Write only campaign.json and runs.csv.
    #[arg(long)]
    pub no_plots: bool,
}

/// Runs the campaign or its shard ([`campaign::run_command`]), or merges shards
/// ([`campaign::merge_command`]).
pub fn run(args: &CampaignArgs) -> Result<()> {
    if let Some(CampaignAction::Merge(m)) = &args.action {
        return campaign::merge_command(&m.dirs, &m.out, !m.no_plots);
    }
    campaign::run_command(&CampaignOptions {
        runs: args.runs,
        out: args.out.clone(),
        controller: args.controller.into(),
        base: (&args.base).into(),
        position_radius_m: args.position_radius_m,
        velocity_radius_m_s: args.velocity_radius_m_s,
        angular_velocity_radius_rad_s: args.angular_velocity_radius_rad_s,
        half_turns: !args.no_half_turns,
        converged_position_m: args.converged_position_m,
        converged_attitude_deg: args.converged_attitude_deg,
        converged_after_s: args.converged_after_s,
        plots: !args.no_plots,
        threads: args.threads,
        shard: args.shard,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every spelling on the command line names the controller of the same label.
    #[test]
    fn controller_spellings_map_to_their_controllers() {
        for v in ControllerArg::value_variants() {
            let name = v.to_possible_value().map(|p| p.get_name().to_string());
            assert_eq!(
                name,
                Some(ControllerKind::from(*v).label().replace('_', "-"))
            );
        }
    }
}
