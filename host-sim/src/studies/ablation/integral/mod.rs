//! The bounded integral action ([`controller_core::integral`]) measured against the paper's law
//! without it, on the same runs (the fourth part of `host-sim ablation`).
//!
//! For each perturbation case of [`CASES`] a campaign of `runs` runs is flown twice, with and
//! without the integral action: same seeds, hence the same starts (the seven starts exactly 180°
//! from `R_d(0)` first, then Haar-random attitudes in the campaign's default offset balls) and
//! the same perturbation draws. Only [`controller_core::Gains::integral`] differs.
//!
//! - A fixed plant mass error flies a clone of the scenario whose `vehicle.mass_kg` is scaled
//!   (the plant's mass), while the law keeps the nominal scenario's vehicle (the model).
//! - Forces are given as fractions of the nominal weight `m g`; the gusts have a 0.5 s
//!   correlation time.
//! - Samples are checked against the bounds of the gains flown: the paper's (Theorem 1–2 and
//!   the tight bounds) without the integral action, the extended ones of [`controller_core::certify`]
//!   (Theorem 1 interval, Lemma 1 and Theorem 2 with the integral terms) with it.
//!
//! The integral gains are the scenario's `gains.integral` when it has them, else
//! [`default_integral_gains`].

mod report;
pub use report::{markdown, IntegralGainsReport, IntegralReport, IntegralRow};

use anyhow::{anyhow, Result};
use controller_core::scalar::{lit, Scalar};
use controller_core::{certify, Certificate, FilterStart, Gains, IntegralGains, Trajectory};
use nalgebra::Vector3;
use rayon::prelude::*;
use serde::Serialize;

use crate::fly::closed_loop::fly;
use crate::fly::controllers::paper::PaperLaw;
use crate::fly::controllers::FlightController;
use crate::model::scenario::{Precision, Scenario};
use crate::runs::metrics::{BoundSet, Convergence, MetricsAccumulator, RunMetrics};
use crate::runs::runner::bound_set;
use crate::runs::sampler::{run_seed, Sampler, SamplerRadii, HALF_TURN_AXES};
use crate::runs::stats::Distribution;

/// Default number of runs per cell (`--integral-runs`).
pub const DEFAULT_RUNS: u64 = 200;

/// Correlation time of the gusts of the cases that have them \[s\].
pub const GUST_TIME_CONSTANT_S: f64 = 0.5;

/// One perturbation case: a row pair of the table.
#[derive(Clone, Copy, Debug, Serialize, PartialEq)]
pub struct Case {
    /// Label in the report.
    pub name: &'static str,
    /// Plant mass over the model's (1 = exact).
    pub plant_mass_factor: f64,
    /// `mass_error_max_fraction` of the runs' perturbations (a uniform draw per run).
    pub mass_error_max_fraction: f64,
    /// `inertia_error_max_fraction` of the runs' perturbations.
    pub inertia_error_max_fraction: f64,
    /// Largest constant force, as a fraction of the nominal weight `m g` (uniform direction,
    /// uniform magnitude per run).
    pub force_max_fraction_of_weight: f64,
    /// Gust force std per inertial axis, as a fraction of the nominal weight `m g`.
    pub gust_std_fraction_of_weight: f64,
    /// A combined case: flown `--integral-combined-runs` times.
    pub combined: bool,
}

/// The cases, in the order of the report.
pub const CASES: [Case; 7] = [
    Case {
        name: "nominal",
        plant_mass_factor: 1.0,
        mass_error_max_fraction: 0.0,
        inertia_error_max_fraction: 0.0,
        force_max_fraction_of_weight: 0.0,
        gust_std_fraction_of_weight: 0.0,
        combined: false,
    },
    Case {
        name: "plant mass +20 %",
        plant_mass_factor: 1.2,
        mass_error_max_fraction: 0.0,
        inertia_error_max_fraction: 0.0,
        force_max_fraction_of_weight: 0.0,
        gust_std_fraction_of_weight: 0.0,
        combined: false,
    },
    Case {
        name: "plant mass -20 %",
        plant_mass_factor: 0.8,
        mass_error_max_fraction: 0.0,
        inertia_error_max_fraction: 0.0,
        force_max_fraction_of_weight: 0.0,
        gust_std_fraction_of_weight: 0.0,
        combined: false,
    },
    Case {
        name: "constant force <= 10 % of weight",
        plant_mass_factor: 1.0,
        mass_error_max_fraction: 0.0,
        inertia_error_max_fraction: 0.0,
        force_max_fraction_of_weight: 0.1,
        gust_std_fraction_of_weight: 0.0,
        combined: false,
    },
    Case {
        name: "gusts (2 % of weight, 0.5 s)",
        plant_mass_factor: 1.0,
        mass_error_max_fraction: 0.0,
        inertia_error_max_fraction: 0.0,
        force_max_fraction_of_weight: 0.0,
        gust_std_fraction_of_weight: 0.02,
        combined: false,
    },
    Case {
        name: "mass, inertia +-20 %, force (no gusts)",
        plant_mass_factor: 1.0,
        mass_error_max_fraction: 0.2,
        inertia_error_max_fraction: 0.2,
        force_max_fraction_of_weight: 0.1,
        gust_std_fraction_of_weight: 0.0,
        combined: true,
    },
    Case {
        name: "all: mass, inertia +-20 %, force, gusts",
        plant_mass_factor: 1.0,
        mass_error_max_fraction: 0.2,
        inertia_error_max_fraction: 0.2,
        force_max_fraction_of_weight: 0.1,
        gust_std_fraction_of_weight: 0.02,
        combined: true,
    },
];

/// Index in [`CASES`] of the case with every perturbation (mass, inertia, force, gusts).
pub const COMBINED_CASE: usize = CASES.len() - 1;

impl Case {
    /// The scenario the plant flies: `base` with its vehicle mass scaled by
    /// [`Self::plant_mass_factor`] and the case's perturbation keys set (the other
    /// `[perturbations]` keys of `base` are kept).
    pub fn plant_scenario(&self, base: &Scenario) -> Scenario {
        let weight_n = base.vehicle.mass_kg * base.vehicle.gravity_m_s2;
        let mut s = base.clone();
        s.vehicle.mass_kg *= self.plant_mass_factor;
        let p = &mut s.perturbations;
        p.mass_error_max_fraction = self.mass_error_max_fraction;
        p.inertia_error_max_fraction = self.inertia_error_max_fraction;
        p.force_disturbance_max_N = self.force_max_fraction_of_weight * weight_n;
        p.gust_force_std_N = self.gust_std_fraction_of_weight * weight_n;
        if self.gust_std_fraction_of_weight > 0.0 {
            p.gust_time_constant_s = GUST_TIME_CONSTANT_S;
        }
        s
    }
}

/// Fraction of `M_p` the default integral level takes on each axis.
pub const DEFAULT_LEVEL_FRACTION_OF_M_P: f64 = 0.25;

/// The integral gains flown when the scenario has none:
///
/// - `k_i = 1 /s³`, `k_η = 5 /s`: with the paper's position gains (`k_p = 9`, `k_v = 6`,
///   `k_f = 2`, `k_s = 20`) the per-axis quartic's roots are `−4.6 ± 0.55 j` and
///   `−0.90 ± 0.55 j`: Routh–Hurwitz holds with margin
///   ([`controller_core::integral_stability`]), and the slowest mode decays in about 1 s;
/// - `R_i = 1 m/s³` per axis;
/// - `M_i = M_p / 4` per axis (0.5 m/s² for the paper's `M_p = 2`). The level is kept well
///   below `M_p` on purpose: the estimate integrates `z₁` during the whole transient of a large
///   start, so it can sit at its level when the vehicle arrives; if `M_i` (plus the
///   disturbance) is close to `M_p`, the saturated position feedback can no longer overpower it
///   and the vertical axis enters a growing oscillation (measured on the paper's start with
///   `M_i,z = 2.45 m/s²`: `|p − p_d|` grows to 50 m by 60 s). The price: a disturbance larger
///   than `M_i` per axis (a 20 % mass error is 1.96 m/s² vertically) is only partly removed.
pub fn default_integral_gains(scenario: &Scenario) -> IntegralGains<f64> {
    IntegralGains {
        feedforward_scale: None,
        gain: 1.0,
        level: Vector3::repeat(DEFAULT_LEVEL_FRACTION_OF_M_P * scenario.gains.M_p),
        rate: Vector3::repeat(1.0),
        bandwidth: 5.0,
        observer: None,
    }
}

/// The integral gains flown for `scenario` and where they come from (`"scenario"` or
/// `"default"`).
pub fn integral_gains_of(scenario: &Scenario) -> (IntegralGains<f64>, &'static str) {
    match scenario.gains::<f64>().integral {
        Some(i) => (i, "scenario"),
        None => (default_integral_gains(scenario), "default"),
    }
}

/// `gains` in scalar `T`.
fn gains_in<T: Scalar>(scenario: &Scenario, integral: Option<&IntegralGains<f64>>) -> Gains<T> {
    let mut g = scenario.gains::<T>();
    g.integral = integral.map(|i| IntegralGains {
        gain: lit(i.gain),
        level: i.level.map(lit),
        rate: i.rate.map(lit),
        bandwidth: lit(i.bandwidth),
        observer: i.observer.map(|o| controller_core::ObserverGains {
            velocity_gain: lit(o.velocity_gain),
            disturbance_gain: lit(o.disturbance_gain),
            error_limit: lit(o.error_limit),
        }),
        feedforward_scale: i
            .feedforward_scale
            .map(|f| controller_core::FeedforwardScaleGains {
                gain: lit(f.gain),
                excitation: lit(f.excitation),
                level: lit(f.level),
                rate: lit(f.rate),
                tracking_limit: lit(f.tracking_limit),
            }),
    });
    g
}

/// The paper's law for `scenario` at its precision, with the integral action `integral` (or
/// none).
///
/// Errors: the law refuses the parameters.
pub fn law(
    scenario: &Scenario,
    integral: Option<&IntegralGains<f64>>,
) -> Result<Box<dyn FlightController>> {
    Ok(match scenario.simulation.precision {
        Precision::F32 => Box::new(PaperLaw::<f32>::with_gains(
            scenario,
            gains_in(scenario, integral),
        )?),
        Precision::F64 => Box::new(PaperLaw::<f64>::with_gains(
            scenario,
            gains_in(scenario, integral),
        )?),
    })
}

/// The extended certificate of `scenario` with `integral` (f64, filters starting at zero).
///
/// Errors: the parameters are refused (e.g. `M_p + M_i,z ≥ g − K_a3`).
pub fn extended_certificate(
    scenario: &Scenario,
    integral: &IntegralGains<f64>,
) -> Result<Certificate<f64>> {
    certify(
        &scenario.vehicle(),
        &scenario.limits(),
        &gains_in(scenario, Some(integral)),
        &scenario.trajectory::<f64>().constants(),
        FilterStart::Zero,
    )
    .map_err(|e| anyhow!("{}", crate::model::scenario::describe(&e)))
}

/// The bounds samples are checked against with the integral action on: the extended
/// Theorem 1 interval (through the scenario's thrust mode) and Theorem 2 torques; the tight
/// bounds are added by [`run_integral`] when the gains are the scenario's own.
///
/// Errors: as [`extended_certificate`], or the thrust mode's floor is above `T_min`.
pub fn extended_bound_set(scenario: &Scenario, integral: &IntegralGains<f64>) -> Result<BoundSet> {
    let cert = extended_certificate(scenario, integral)?;
    let [low, high] = scenario
        .thrust_interval(&cert)
        .map_err(|e| anyhow!("{e}"))?;
    Ok(BoundSet {
        thrust_min_N: low,
        thrust_max_N: high,
        torque_max_Nm: cert.bounds.torque_max.into(),
        limit_thrust_N: scenario.limits.thrust_max_N,
        limit_torque_Nm: scenario.limits.torque_max_Nm,
        tight: None,
    })
}

/// Convergence judged as `campaign` does by default: settled [`Convergence::default`]'s 25 s
/// into the paper's 30 s runs, i.e. 5 s before the end of the scenario's runs, so a design
/// written for longer runs (`design --duration-s`) is judged on its own horizon.
pub fn convergence_of(scenario: &Scenario) -> Convergence {
    let d = Convergence::default();
    Convergence {
        after_s: scenario.simulation.duration_s - (PAPER_DURATION_S - d.after_s),
        ..d
    }
}

/// The paper's run length \[s\] (Section VI), which [`Convergence::default`] is set for.
const PAPER_DURATION_S: f64 = 30.0;

/// Flies `runs` runs of `case` on `base` (`integral` on or off) and summarises them.
#[allow(clippy::too_many_arguments)]
fn cell(
    base: &Scenario,
    case: &Case,
    integral: Option<&IntegralGains<f64>>,
    bounds: BoundSet,
    sampler: &Sampler,
    seed: u64,
    runs: u64,
) -> Result<IntegralRow> {
    let plant = case.plant_scenario(base);
    let convergence = convergence_of(base);
    let sim = &base.simulation;
    // Built once to refuse bad gains before the runs; each run builds its own.
    law(base, integral)?;
    let flown: Vec<(bool, Option<RunMetrics>)> = (0..runs)
        .into_par_iter()
        .map(|i| {
            let seed = run_seed(seed, i);
            let initial = sampler.sample(i, seed, true);
            let mut acc = MetricsAccumulator::new(
                convergence,
                bounds,
                sim.duration_s,
                sim.controller_period_s,
            );
            // The campaign's noise stream (crate::runs::runner::run_one).
            let noise_seed = run_seed(seed, u64::MAX);
            let metrics = law(base, integral)
                .and_then(|mut c| {
                    fly(&plant, c.as_mut(), &initial.state, noise_seed, |s| {
                        acc.push(s)
                    })
                })
                .ok()
                .map(|_| acc.finish());
            ((i as usize) < HALF_TURN_AXES.len(), metrics)
        })
        .collect();
    let done: Vec<&RunMetrics> = flown.iter().filter_map(|(_, m)| m.as_ref()).collect();
    let half: Vec<&RunMetrics> = flown
        .iter()
        .filter(|(h, _)| *h)
        .filter_map(|(_, m)| m.as_ref())
        .collect();
    let converged = done.iter().filter(|m| m.converged).count();
    let mm = |m: &&RunMetrics| 1e3 * m.steady_position_error_m;
    Ok(IntegralRow {
        case: case.name.into(),
        integral: integral.is_some(),
        runs: flown.len(),
        refused: flown.len() - done.len(),
        converged,
        converged_percent: 100.0 * converged as f64 / (flown.len().max(1) as f64),
        steady_error_converged_mm: Distribution::of(done.iter().filter(|m| m.converged).map(mm)),
        steady_error_all_mm: Distribution::of(done.iter().map(mm)),
        samples_outside_a_priori: done.iter().map(|m| m.samples_outside_a_priori).sum(),
        samples_above_tight: bounds
            .tight
            .map(|_| done.iter().map(|m| m.samples_above_tight).sum()),
        half_turn_time_to_90deg_s: Distribution::of(
            half.iter().filter_map(|m| m.attitude_below_90deg_s),
        ),
        half_turn_settling_s: Distribution::of(half.iter().filter_map(|m| m.settling_time_s)),
        half_turn_settled: half.iter().filter(|m| m.settling_time_s.is_some()).count(),
    })
}

/// Runs every case of [`CASES`] with and without the integral action on `scenario`: `runs`
/// runs per cell (`combined_runs` for the combined cases), from `seed`. The rows without it
/// are checked against the paper's bounds (and tight bounds) of the same gains with the
/// integral action off; the rows with it against the extended certificate's, and, when the
/// integral gains are the scenario's own, its tight bounds too.
///
/// Errors: the scenario is invalid, or its integral gains are refused or leave no thrust
/// (`certify`).
pub fn run_integral(
    scenario: &Scenario,
    seed: u64,
    runs: u64,
    combined_runs: u64,
) -> Result<IntegralReport> {
    let (gains, source) = integral_gains_of(scenario);
    let cert = extended_certificate(scenario, &gains)?;
    // Without: the paper's bounds of the same gains with the integral action off.
    let mut without = scenario.clone();
    without.gains.integral = None;
    let bounds_without = bound_set(&without)?;
    let mut bounds_with = extended_bound_set(scenario, &gains)?;
    if source == "scenario" {
        // The tight bounds cover the scenario's own integral action (and feedforward scale).
        let tight = crate::bounds::certificate::scenario_tight_bounds(scenario)?;
        bounds_with.tight = Some(crate::bounds::certificate::tight_limits(&tight));
    }
    let sampler = Sampler::new(scenario, SamplerRadii::default())?;
    let violations: Vec<String> = cert
        .violations()
        .map(|c| format!("{}: {:.4} vs {:.4}", c.name, c.lhs, c.rhs))
        .collect();
    let mut rows = Vec::new();
    for case in &CASES {
        let n = if case.combined { combined_runs } else { runs };
        // Without: the scenario with the integral action removed (its thrust cap is then the
        // paper's T_max, not the extended one).
        for (base, integral, bounds) in [
            (&without, None, bounds_without),
            (scenario, Some(&gains), bounds_with),
        ] {
            rows.push(cell(base, case, integral, bounds, &sampler, seed, n)?);
        }
    }
    Ok(IntegralReport {
        definitions: format!(
            "Each case flies the same runs (seed {seed}; the seven 180-deg starts first, then \
             Haar attitudes in the default offset balls) without and with the integral action. \
             steady error: mean |p - p_d| over the last 5 s. samples outside: against the \
             paper's bounds without, the extended certificate's with. half-turn: the seven \
             180-deg starts, time to attitude error < 90 deg and settling. Plant mass cases \
             scale the plant's mass only (the law keeps the model's). Forces are fractions of \
             the nominal weight; gusts with tau = {GUST_TIME_CONSTANT_S} s. {}",
            convergence_of(scenario).describe()
        ),
        gains: IntegralGainsReport {
            k_i: gains.gain,
            M_i_m_s2: gains.level.into(),
            R_i_m_s3: gains.rate.into(),
            k_eta: gains.bandwidth,
        },
        gains_source: source.into(),
        bounds_without,
        bounds_with,
        extended_certificate_holds: violations.is_empty(),
        extended_violations: violations,
        rows,
    })
}

#[cfg(test)]
mod tests;
