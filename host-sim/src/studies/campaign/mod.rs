//! Robustness campaigns: many closed-loop runs from sampled initial conditions, their
//! statistics, and their files (`campaign.json`, `runs.csv`, PNG plots).
//!
//! [`sampler`] draws the initial conditions, [`runner`] flies them in parallel, [`metrics`]
//! measures one run, [`stats`] summarises the runs, [`output`] writes the files and [`figures`]
//! draws the non-time-series plots; [`options`] holds the jobs' options and [`command`] runs
//! the `campaign` job. Across machines: [`shard`] picks a process's share of the runs,
//! [`partial`] writes and reads its partial result and [`merge`] combines the shards into the
//! files a single process would write.

pub mod command;
pub mod figures;
pub mod merge;
pub mod options;
pub mod output;
pub mod partial;
pub mod shard;

// The run toolkit campaigns fly with, also reachable from here (the paths campaigns were first
// published under).
pub use crate::runs::{metrics, runner, sampler, stats, trace};

pub use crate::runs::metrics::{BoundSet, Convergence, RunMetrics, TightLimits};
pub use crate::runs::runner::{run_campaign, CampaignConfig, RunResult};
pub use crate::runs::sampler::{Sampler, SamplerRadii};
pub use crate::runs::stats::{summarise, CampaignStats};
pub use command::{merge_command, run_command};
pub use options::{BaseOptions, CampaignOptions};
pub use shard::Shard;
