//! The options of the three campaign-style jobs (`campaign`, `ablation`, `compare`): the base
//! scenario with its overrides and the seed ([`BaseOptions`]), and a campaign's own
//! ([`CampaignOptions`]).

use std::path::PathBuf;

use anyhow::{bail, Result};

use crate::fly::controllers::ControllerKind;
use crate::model::scenario::{ControllerOverrides, PlantKind, Precision, Scenario};

/// Options shared by the campaign, the ablations and the comparison: the base scenario and the
/// seed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BaseOptions {
    /// Base scenario file (TOML); `None`: the embedded paper scenario. Its `[initial]` table is
    /// replaced by the sampled initial conditions; its `[perturbations]` apply to every run.
    pub scenario: Option<PathBuf>,
    /// Campaign seed: run i draws from splitmix(seed, i), so results do not depend on threads
    /// (the command line's default: 1).
    pub seed: u64,
    /// Simulated duration of every run \[s\], overriding `simulation.duration_s`.
    pub duration_s: Option<f64>,
    /// Controller rate \[Hz\], overriding `simulation.controller_period_s` (and capping the
    /// plant step at one controller period).
    pub controller_rate_hz: Option<f64>,
    /// Clip thrust and torque to the physical limits before the plant (or-ed with the
    /// scenario's `simulation.clip_to_limits`).
    pub clip: bool,
    /// Controller precision for the paper's law, overriding `simulation.precision`.
    pub precision: Option<Precision>,
    /// Plant, overriding `simulation.plant` (`PlantKind::Rotors` flies every controller's
    /// `(T, τ)` through the firmware's mixer and the rotors).
    pub plant: Option<PlantKind>,
    /// Vehicle file whose `[vehicle]`, `[rotors]` and `[drag]` replace the scenario's
    /// ([`Scenario::with_vehicle`]).
    pub vehicle: Option<PathBuf>,
    /// Motor time constant \[s\], overriding `[perturbations] motor_time_constant_s` (on the
    /// rotor plant it replaces the vehicle's, e.g. twice it for a robustness campaign).
    pub motor_time_constant_s: Option<f64>,
    /// `[controller]` overrides (the thrust law and its parameters).
    pub controller: ControllerOverrides,
}

impl BaseOptions {
    /// The scenario with the overrides applied.
    ///
    /// Errors: the scenario or vehicle file cannot be read or is invalid; an override is not
    /// finite and > 0; `plant = rotors` without rotors.
    pub fn scenario(&self) -> Result<Scenario> {
        let mut s = match &self.scenario {
            Some(p) => Scenario::load(p)?,
            None => Scenario::paper(),
        };
        if let Some(d) = self.duration_s {
            if !(d.is_finite() && d > 0.0) {
                bail!("--duration-s must be finite and > 0, got {d}");
            }
            s.simulation.duration_s = d;
        }
        if let Some(hz) = self.controller_rate_hz {
            if !(hz.is_finite() && hz > 0.0) {
                bail!("--controller-rate-hz must be finite and > 0, got {hz}");
            }
            s.simulation.controller_period_s = 1.0 / hz;
            s.simulation.plant_step_s = s.simulation.plant_step_s.min(1.0 / hz);
        }
        s.simulation.clip_to_limits |= self.clip;
        if let Some(p) = self.precision {
            s.simulation.precision = p;
        }
        let s = s
            .with_plant_overrides(
                self.vehicle.as_deref(),
                self.plant,
                self.motor_time_constant_s,
            )?
            .with_controller_overrides(&self.controller);
        s.validate().map_err(|e| anyhow::anyhow!("{e}"))?;
        Ok(s)
    }
}

/// What the `campaign` job runs (the command line's defaults in parentheses).
#[derive(Clone, Debug, PartialEq)]
pub struct CampaignOptions {
    /// Number of runs (1000).
    pub runs: u64,
    /// Output directory, created; files overwritten (`out/campaign`).
    pub out: PathBuf,
    /// Controller flown in every run (the paper's law).
    pub controller: ControllerKind,
    /// Scenario, seed and overrides.
    pub base: BaseOptions,
    /// Radius of the position-offset ball around p_d(0) \[m\] (`SamplerRadii::default()`).
    pub position_radius_m: f64,
    /// Radius of the velocity-offset ball around the reference velocity \[m/s\]
    /// (`SamplerRadii::default()`).
    pub velocity_radius_m_s: f64,
    /// Radius of the body angular-velocity ball \[rad/s\] (`SamplerRadii::default()`).
    pub angular_velocity_radius_rad_s: f64,
    /// Include the fixed 180° starts (`false`: all runs Haar-uniform) (`true`).
    pub half_turns: bool,
    /// Convergence: position error threshold \[m\] (`Convergence::default()`).
    pub converged_position_m: f64,
    /// Convergence: attitude error threshold \[deg\] (`Convergence::default()`).
    pub converged_attitude_deg: f64,
    /// Convergence: settled by this time \[s\], at most the run's duration (`None`: 5 s before
    /// the end, [`crate::studies::campaign::Convergence::for_duration`]; 25 s for the paper's 30 s runs).
    pub converged_after_s: Option<f64>,
    /// Write the plots too (`false`: only campaign.json and runs.csv) (`true`).
    pub plots: bool,
    /// Worker threads (`None`: one per core); the results do not depend on it.
    pub threads: Option<usize>,
    /// Run only this share of the runs and write its partial result (`shard.json`) instead of
    /// the campaign's files (`None`: all runs).
    pub shard: Option<super::shard::Shard>,
}
