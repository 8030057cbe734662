//! Robustness campaigns: many closed-loop runs from sampled initial conditions, their
//! statistics, and their files (`campaign.json`, `runs.csv`, PNG plots).
//!
//! [`sampler`] draws the initial conditions, [`runner`] flies them in parallel, [`metrics`]
//! measures one run, [`stats`] summarises the runs, [`output`] writes the files and [`figures`]
//! draws the non-time-series plots; [`options`] holds the jobs' options and [`command`] runs
//! the `campaign` job.

pub mod command;
pub mod figures;
pub mod metrics;
pub mod options;
pub mod output;
pub mod runner;
pub mod sampler;
pub mod stats;
pub mod trace;

pub use command::run_command;
pub use metrics::{BoundSet, Convergence, RunMetrics, TightLimits};
pub use options::{BaseOptions, CampaignOptions};
pub use runner::{run_campaign, CampaignConfig, RunResult};
pub use sampler::{Sampler, SamplerRadii};
pub use stats::{summarise, CampaignStats};
