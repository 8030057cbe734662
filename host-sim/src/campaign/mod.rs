//! Robustness campaigns: many closed-loop runs from sampled initial conditions, their
//! statistics, and their files (`campaign.json`, `runs.csv`, PNG plots).
//!
//! [`sampler`] draws the initial conditions, [`runner`] flies them in parallel, [`metrics`]
//! measures one run, [`stats`] summarises the runs, [`output`] writes the files and [`figures`]
//! draws the non-time-series plots.

pub mod figures;
pub mod metrics;
pub mod output;
pub mod runner;
pub mod sampler;
pub mod stats;
pub mod trace;

pub use metrics::{BoundSet, Convergence, RunMetrics};
pub use runner::{run_campaign, CampaignConfig, RunResult};
pub use sampler::{Sampler, SamplerRadii};
pub use stats::{summarise, CampaignStats};
