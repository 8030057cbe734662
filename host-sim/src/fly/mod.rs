//! How one flight is flown: scenario files ([`scenario`]), the closed loop every run uses
//! ([`closed_loop`]), the controllers that close it ([`controllers`]: the paper's law and the
//! baselines) and the main run with its diagnostics and summary ([`sim`]).

pub mod closed_loop;
pub mod controllers;
pub mod scenario;
pub mod sim;
