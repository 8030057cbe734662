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
pub mod metrics;
pub mod options;
pub mod output;
pub mod partial;
pub mod runner;
pub mod sampler;
pub mod shard;
pub mod stats;
pub mod trace;

pub use command::{merge_command, run_command};
pub use metrics::{BoundSet, Convergence, RunMetrics, TightLimits};
pub use options::{BaseOptions, CampaignOptions};
pub use runner::{run_campaign, CampaignConfig, RunResult};
pub use sampler::{Sampler, SamplerRadii};
pub use shard::Shard;
pub use stats::{summarise, CampaignStats};
