//! The campaign half of the rate study: a robustness campaign of the paper's law (f32, as on
//! the MCU) on the rotor plant (the firmware's mixer, four rotors with first-order motor lag)
//! at one law rate, reduced to a row.

use std::path::PathBuf;

use anyhow::Result;
use serde::Serialize;

use crate::fly::controllers::ControllerKind;
use crate::model::scenario::{PlantKind, Precision};
use crate::studies::campaign::{
    run_campaign, stats::Distribution, BaseOptions, CampaignConfig, Convergence, SamplerRadii,
};

/// What every rate's campaign flies besides the rate.
#[derive(Clone, Debug, PartialEq)]
pub struct CampaignPlan {
    /// Runs per rate.
    pub runs: u64,
    /// Campaign seed (the same initial conditions at every rate).
    pub seed: u64,
    /// Vehicle file flown on the rotor plant (its rotors and motor time constant).
    pub vehicle: PathBuf,
    /// Motor time constant \[s\] replacing the vehicle's (`None`: the vehicle's).
    pub motor_time_constant_s: Option<f64>,
    /// Worker threads (`None`: one per core); the results do not depend on it.
    pub threads: Option<usize>,
}

/// One campaign at one rate.
#[derive(Clone, Debug, Serialize, PartialEq)]
#[allow(non_snake_case)]
pub struct CampaignRow {
    /// The law's rate \[Hz\].
    pub rate_hz: u32,
    /// Runs.
    pub runs: u64,
    /// Fraction of the runs settled by the convergence time \[dimensionless\].
    pub converged_fraction: f64,
    /// Settling time, median and 99th percentile over the settled runs \[s\].
    pub settling_s: [Option<f64>; 2],
    /// Steady-state position error (mean over the last 5 s of a run), median and largest
    /// over the runs \[m\].
    pub steady_error_m: [Option<f64>; 2],
    /// Largest `|τ_i|` commanded in any run, per axis \[N m\].
    pub torque_peak_Nm: [f64; 3],
    /// Theorem 2's per-axis torque bound \[N m\].
    pub torque_bound_Nm: [f64; 3],
    /// Smallest `1 − peak_i / bound_i` over the axes \[dimensionless\].
    pub torque_margin: f64,
    /// Largest thrust commanded in any run \[N\] and Theorem 1's `T_max` \[N\].
    pub thrust_peak_and_bound_N: [f64; 2],
    /// Runs with at least one sample outside the a-priori bounds.
    pub runs_outside_a_priori: u64,
    /// Fraction of the samples in which the mixer gave something up \[dimensionless\].
    pub mixer_gave_up_fraction: f64,
    /// Runs that stopped with an error.
    pub failed_runs: u64,
}

/// Runs the campaign of `plan` at `rate_hz` \[Hz\] (paper scenario, Haar and 180° starts,
/// default radii and convergence) and reduces it to a row.
///
/// Errors: the vehicle file or the scenario is invalid.
pub fn fly(plan: &CampaignPlan, rate_hz: u32) -> Result<CampaignRow> {
    let base = BaseOptions {
        seed: plan.seed,
        controller_rate_hz: Some(f64::from(rate_hz)),
        precision: Some(Precision::F32),
        plant: Some(PlantKind::Rotors),
        vehicle: Some(plan.vehicle.clone()),
        motor_time_constant_s: plan.motor_time_constant_s,
        ..BaseOptions::default()
    };
    let scenario = base.scenario()?;
    let bounds = crate::runs::runner::paper_bound_set(&scenario)?;
    let config = CampaignConfig {
        scenario,
        controller: ControllerKind::Paper,
        runs: plan.runs,
        seed: plan.seed,
        radii: SamplerRadii::default(),
        half_turns: true,
        convergence: Convergence::default(),
        progress: false,
        threads: plan.threads,
    };
    let results = run_campaign(&config)?;
    let metrics: Vec<_> = results.iter().filter_map(|r| r.metrics.as_ref()).collect();
    let settling = Distribution::of(metrics.iter().filter_map(|m| m.settling_time_s));
    let steady = Distribution::of(metrics.iter().map(|m| m.steady_position_error_m));
    let mut torque_peak = [0.0f64; 3];
    let mut thrust_peak = 0.0f64;
    let (mut samples, mut gave_up) = (0u64, 0u64);
    for m in &metrics {
        for (peak, seen) in torque_peak.iter_mut().zip(m.torque_abs_max_Nm) {
            *peak = peak.max(seen);
        }
        thrust_peak = thrust_peak.max(m.thrust_max_N);
        if let Some(c) = &m.mixer {
            samples += c.samples;
            gave_up += c.samples_given_up;
        }
    }
    let torque_margin = torque_peak
        .iter()
        .zip(bounds.torque_max_Nm)
        .map(|(peak, bound)| 1.0 - peak / bound)
        .fold(f64::INFINITY, f64::min);
    Ok(CampaignRow {
        rate_hz,
        runs: plan.runs,
        converged_fraction: metrics.iter().filter(|m| m.converged).count() as f64
            / plan.runs.max(1) as f64,
        settling_s: [settling.p50, settling.p99],
        steady_error_m: [steady.p50, steady.max],
        torque_peak_Nm: torque_peak,
        torque_bound_Nm: bounds.torque_max_Nm,
        torque_margin,
        thrust_peak_and_bound_N: [thrust_peak, bounds.thrust_max_N],
        runs_outside_a_priori: metrics
            .iter()
            .filter(|m| m.samples_outside_a_priori > 0)
            .count() as u64,
        mixer_gave_up_fraction: gave_up as f64 / samples.max(1) as f64,
        failed_runs: (results.len() - metrics.len()) as u64,
    })
}
