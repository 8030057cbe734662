//! host-sim: the controller-core law against a desktop rigid-body model.
//!
//! [`scenario`] reads TOML scenarios (the paper's is embedded), [`plant`] integrates
//! eq:FullDynamics, [`sim`] closes the loop, and [`output`] writes CSV, PNG plots and
//! `summary.json`.

pub mod ablation;
pub mod campaign;
pub mod cli;
pub mod closed_loop;
pub mod compare;
pub mod controllers;
pub mod experiments;
pub mod m4f;
pub mod output;
pub mod perturbation;
pub mod pil;
pub mod plant;
pub mod report;
pub mod scenario;
pub mod sil;
pub mod sim;
pub mod so3;
