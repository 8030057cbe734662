//! What a flight is checked against, built once from its scenario and passed down: the paper's
//! certificate (Assumption 1, Theorems 1-2, Lemma 1) and the tight a-priori bounds
//! (docs/tight-bounds.md).

use anyhow::Result;
use controller_core::Certificate;

use crate::bounds::certificate::{scenario_certificate, scenario_tight_bounds};
use crate::bounds::tight::TightBounds;
use crate::model::scenario::Scenario;

/// The bounds one scenario's run is checked against and reports.
#[derive(Clone, Debug)]
pub struct FlightSetup {
    /// The paper's certificate in f64 (filters starting at zero): the thrust interval \[N\],
    /// the per-axis torque bound [N m] (body frame), `|ω_d|` [rad/s], `|ω̇_d|` [rad/s²] and
    /// every condition with both sides.
    pub certificate: Certificate<f64>,
    /// The tight a-priori bounds on the same quantities (branch and bound, about a second).
    pub tight: TightBounds,
}

impl FlightSetup {
    /// Computes both for `scenario`.
    ///
    /// Errors: the scenario's parameters are refused (named by scenario key).
    pub fn new(scenario: &Scenario) -> Result<Self> {
        Ok(Self {
            certificate: scenario_certificate(scenario)?,
            tight: scenario_tight_bounds(scenario)?,
        })
    }
}
