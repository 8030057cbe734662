//! How one flight is flown: the bounds it is checked against, built once ([`setup`]), the
//! closed loop every run uses
//! ([`closed_loop`]), the controllers that close it ([`controllers`]: the paper's law and the
//! baselines) and the main run with its diagnostics and summary ([`sim`]).

pub mod closed_loop;
pub mod controllers;
pub mod files;
pub mod setup;
pub mod sim;
