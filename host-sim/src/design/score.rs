//! A scenario file judged as `design` judges its candidates: the certificate against the
//! scenario's own rotors (every condition, the certified `(T, τ)` set's fit with the margin,
//! what the firmware's gate re-checks) and the objective's runs (docs/design.md, "Objective").
//! For hand-tuning: change a gain in a design's `scenario.toml`, run `host-sim score`, and see
//! at once whether the certificate still holds and what the change costs or buys, without a
//! whole `design` search.

use anyhow::{anyhow, Result};
use controller_core::Trajectory as _;
use serde::Serialize;

use super::attitude_terms::{sample_attitude_terms, AttitudeTermsSample};
use super::authority::{set_margin, RotorFit, RotorSet};
use super::certificate::certify_design_with;
use super::evaluate::{evaluate, Evaluation};
use super::fit_binding::{fit_binding, FitBinding};
use super::integral::IntegralSpec;
use super::reference::Reference;
use crate::model::scenario::Scenario;

/// One violated condition of the certificate: `lhs > rhs` should hold.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Violated {
    /// The condition's stable name, e.g. `"local_regime.torque_max_yaw"`.
    pub name: &'static str,
    /// Its left-hand side (units as the condition's: N, N m or m/s²).
    pub lhs: f64,
    /// Its right-hand side (same units).
    pub rhs: f64,
}

/// What [`score_scenario`] found.
#[derive(Clone, Debug, Serialize)]
pub struct ScenarioScore {
    /// Every condition holds and the certified set fits the rotors with the margin
    /// ([`super::certificate::Certified::ok`]): what `design` requires of a design.
    pub certified: bool,
    /// What the firmware's gate re-checks on board ([`super::certificate::Certified::paper_certified`]).
    pub gate_certified: bool,
    /// The conditions that fail (global, integral, tilt priority, local regime), in the
    /// certificate's order; empty when every one holds.
    pub violated: Vec<Violated>,
    /// Smallest headroom of the certified set over the rotors, fraction of the rotor range
    /// (negative: it does not fit; compare with the requested margin).
    pub fit_headroom: f64,
    /// The same for the local regime's torque set (docs/envelope-design.md) over the certified
    /// thrust interval; `None` without a local regime.
    pub local_fit_headroom: Option<f64>,
    /// The margin the fit is judged with (fraction of each rotor's range).
    pub margin: f64,
    /// With airmode, the aligned fit's headroom: the feedforward at zero attitude error over
    /// Theorem 1's whole thrust interval, fraction of the rotor range. At least `margin`:
    /// airmode leaves the thrust alone near convergence and the position loop's convergence is
    /// proven (docs/airmode.md, "What is proven", step 3); below it, shown by simulation only.
    /// `None` without airmode.
    pub aligned_fit_headroom: Option<f64>,
    /// With airmode, the rotor pair that binds the certified set's shadow fit and what each
    /// part of the set takes of it (docs/design.md, "Scoring an edited design"); `None`
    /// without airmode (the set fit binds a single rotor at an end of the thrust interval).
    pub binding: Option<FitBinding>,
    /// The same for the local regime's set; `None` without airmode or a local regime.
    pub local_binding: Option<FitBinding>,
    /// With tilt priority and a binding pair: its attitude terms (radial MRP, trace, turn-over)
    /// sampled together along the certified set's binding direction, beside what the set
    /// charges them apart (a measurement, not a bound; [`super::attitude_terms`]).
    pub attitude_terms: Option<AttitudeTermsSample>,
    /// The objective's runs and its value (lower is better; `≥ PENALTY` when a run does not
    /// converge).
    pub evaluation: Evaluation,
}

/// Grid points per half axis of the attitude terms' sample: 81³ points, about 0.1 s. On the x500
/// design, with its turn-over level and with 3.5 and 7 times it, the figure moves by less than
/// 0.1 % from 20 to 90 points.
const ATTITUDE_GRID: usize = 40;

/// Judges `scenario` (a design's `scenario.toml`, or any scenario with a `[rotors]` table) as
/// `design` judges a candidate: [`certify_design_with`] on the scenario's rotors with `margin`
/// (a fraction of each rotor's range; airmode's shadow fit when the scenario flies airmode),
/// and [`evaluate`] with the rotors' motor time constant, the upside-down start and the nominal
/// tasks at the reference's start (`p_d(0)`, `ψ_d(0)`), and with `integral` the disturbed hover
/// it covers.
///
/// Errors: no `[rotors]` table; the certificate refuses the parameters (the violated parameter
/// by name); a run refuses the scenario.
pub fn score_scenario(
    scenario: &Scenario,
    integral: Option<&IntegralSpec>,
    margin: f64,
) -> Result<ScenarioScore> {
    let rotors = scenario.rotor_config().ok_or_else(|| {
        anyhow!("score needs the scenario's [rotors] table (the fit is judged on its rotors)")
    })?;
    let fit = if scenario.controller.airmode {
        RotorFit::Airmode
    } else {
        RotorFit::Set
    };
    let certified = certify_design_with(
        &scenario.vehicle::<f64>(),
        &rotors.rotors,
        &scenario.gains::<f64>(),
        &scenario.trajectory::<f64>().constants(),
        margin,
        None,
        fit,
    )?;
    let set = RotorSet::new(&rotors.rotors).map_err(|e| anyhow!("rotor set: {e}"))?;
    let b = &certified.certificate.bounds;
    let local_fit_headroom = certified.certificate.local.as_ref().map(|l| match fit {
        RotorFit::Set => set_margin(&set, (b.thrust_min, b.thrust_max), &l.torque_set),
        RotorFit::Airmode => set.envelope(0.0).shadow_margin(&l.torque_set),
    });
    let envelope = set.envelope(0.0);
    let airmode = fit == RotorFit::Airmode;
    let binding = airmode.then(|| fit_binding(&envelope, &b.torque_set));
    let local_binding = certified
        .certificate
        .local
        .as_ref()
        .filter(|_| airmode)
        .map(|l| fit_binding(&envelope, &l.torque_set));
    let attitude_terms = binding.as_ref().and_then(|pair| {
        let d = pair.newtons_per_newton_metre.into();
        sample_attitude_terms(&scenario.gains::<f64>(), &b.torque_set, &d, ATTITUDE_GRID)
    });
    let reference = Reference {
        trajectory: scenario.trajectory.clone(),
        initial: scenario.initial.clone(),
    };
    let mut hover = scenario.clone();
    hover.trajectory = reference.hover_at_start();
    let evaluation = evaluate(
        scenario,
        &hover,
        (rotors.motor_time_constant_s, integral),
        false,
    )?;
    Ok(ScenarioScore {
        certified: certified.ok(),
        gate_certified: certified.paper_certified(),
        violated: certified
            .certificate
            .violations()
            .map(|k| Violated {
                name: k.name,
                lhs: k.lhs,
                rhs: k.rhs,
            })
            .collect(),
        fit_headroom: certified.margin,
        local_fit_headroom,
        margin,
        aligned_fit_headroom: certified.aligned_margin,
        binding,
        local_binding,
        attitude_terms,
        evaluation,
    })
}

#[cfg(test)]
mod tests;
