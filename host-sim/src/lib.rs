//! host-sim: the controller-core law against a desktop rigid-body model.
//!
//! [`scenario`] reads TOML scenarios (the paper's is embedded), [`plant`] integrates
//! eq:FullDynamics, [`closed_loop`] closes the loop (and [`sim`] flies the paper law in it with
//! its diagnostics), and [`output`] writes CSV, PNG plots and
//! `summary.json`. [`campaign`], [`ablation`] and [`compare`] fly many runs ([`rate_study`]
//! compares the law's rates); [`harness`] flies
//! the firmware itself (software and processor in the loop, Cortex-M4F instruction counts).
//!
//! The command line belongs to the `host-sim` binary (`src/cli/`): the library takes plain
//! option structs ([`harness::sil::SilOptions`], [`harness::pil::PilCommandOptions`],
//! [`campaign::CampaignOptions`], [`ablation::AblationOptions`], [`compare::CompareOptions`])
//! and knows nothing of clap.

pub mod ablation;
pub mod bounds_table;
pub mod campaign;
pub mod closed_loop;
pub mod compare;
pub mod controllers;
pub mod design;
pub mod harness;
pub mod integral_ablation;
pub mod no_dive;
pub mod output;
pub mod perturbation;
pub mod plant;
pub mod rate_study;
pub mod report;
pub mod rotor_plant;
pub mod scenario;
pub mod sim;
pub mod so3;
pub mod tight_bounds;
pub mod tight_certificate;
pub mod vehicle;
