//! One set-up of the law: what the confining set of the admissible states depends on.

use anyhow::{Context, Result};
use controller_core::{
    certify, Certificate, FilterStart, Gains, Limits, Trajectory, TrajectoryConstants, Vehicle,
};

use crate::model::scenario::Scenario;

/// Vehicle, actuator limits, gains, the reference's Assumption 1 constants and where the
/// filters start: everything the admissible states ([`super::sampling`]) and the bounds on them
/// depend on. Limits enter only the paper's certificate ([`Setup::certificate`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Setup {
    /// Mass \[kg\], inertia diagonal [kg m²], gravity [m/s²].
    pub vehicle: Vehicle<f64>,
    /// Actuator limits (`T_max` \[N\], `τ_max` [N m]).
    pub limits: Limits<f64>,
    /// Table I gains.
    pub gains: Gains<f64>,
    /// `K_a12, K_a3, K_j, K_s, K_ν̇, K_ν̈` (Assumption 1).
    pub constants: TrajectoryConstants<f64>,
    /// The start set of the filter states (Lemma 1's `U_l` depends on it).
    pub filter_start: FilterStart,
}

impl Setup {
    /// The paper's set-up (Section VI): Table I, the helix reference, `x_f(0) = 0`.
    pub fn paper() -> Self {
        Self::from_scenario(&Scenario::paper())
    }

    /// The set-up of a scenario, with the filters started at zero as every run of host-sim
    /// does.
    pub fn from_scenario(scenario: &Scenario) -> Self {
        Self {
            vehicle: scenario.vehicle(),
            limits: scenario.limits(),
            gains: scenario.gains(),
            constants: scenario.trajectory().constants(),
            filter_start: FilterStart::Zero,
        }
    }

    /// The paper's bounds for this set-up (Lemma 1, Theorem 2).
    ///
    /// Errors: the parameter `certify` refuses, named.
    pub fn certificate(&self) -> Result<Certificate<f64>> {
        certify(
            &self.vehicle,
            &self.limits,
            &self.gains,
            &self.constants,
            self.filter_start,
        )
        .map_err(|e| anyhow::anyhow!(crate::model::scenario::describe(&e)))
        .context("certifying the set-up")
    }
}
