//! The paper's certificate beside the tight one.
//!
//! [`controller_core::certify`] evaluates Lemma 1 and Theorem 2 as the paper writes them.
//! [`crate::bounds::tight`] bounds the same quantities (`|ω_d|`, `|ω̇_d|`, each `|τ_i|`) by the
//! supremum of the law over the set its saturations and filters confine it to, computed with
//! outward-rounded interval arithmetic. Both bounds are sound; the tight one is smaller. This
//! module puts them side by side and re-checks Theorem 2's torque condition
//! (eq:TorqueMaxConditionsTheorem) with each, so that a condition that fails with the paper's
//! bounds but holds with the tight ones is reported as such. Every other condition (Assumption 1,
//! Theorem 1) does not depend on these bounds and keeps the paper's verdict.

use anyhow::{anyhow, Result};
use controller_core::{certify, Certificate, FilterStart, Trajectory};
use serde::Serialize;

use crate::bounds::tight::{tight_bounds, TightBounds, TightLower, TightOptions};
use crate::model::scenario::Scenario;
use nalgebra::Vector3;

/// One torque condition of Theorem 2 judged with both bounds.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct TightCondition {
    /// The paper's condition name, e.g. `theorem2.torque_max_yaw`.
    pub name: String,
    /// `τ_max,i` [N m] (the actuator's limit, the larger side when the condition holds).
    pub lhs: f64,
    /// The paper's bound on `|τ_i|` [N m] (Theorem 2 as written).
    pub rhs_paper: f64,
    /// The tight bound on `|τ_i|` [N m].
    pub rhs_tight: f64,
    /// `τ_max,i > ` the paper's bound.
    pub holds_paper: bool,
    /// `τ_max,i > ` the tight bound.
    pub holds_tight: bool,
}

impl TightCondition {
    /// "holds", "fails with the paper's bounds, holds with the tight ones", or "fails".
    pub fn verdict(&self) -> &'static str {
        match (self.holds_paper, self.holds_tight) {
            (true, _) => "holds",
            (false, true) => "fails with the paper's bounds, holds with the tight ones",
            (false, false) => "fails with both bounds",
        }
    }
}

/// The tight bounds of one set-up, for `summary.json` (`a_priori.tight`).
#[derive(Clone, Debug, Serialize, PartialEq)]
#[allow(non_snake_case)]
pub struct TightReport {
    /// Per-axis bound on `|τ_i|` [N m], body frame.
    pub torque_max_Nm: [f64; 3],
    /// Bound on `|ω_d|` [rad/s].
    pub angular_velocity_max_rad_s: f64,
    /// Bound on `|ω̇_d|` [rad/s²].
    pub angular_acceleration_max_rad_s2: f64,
    /// Tight over the paper's bound, per axis for the torque.
    pub ratio_to_paper: TightRatios,
    /// The branch and bound's relative gap between its bound and the best value it evaluated.
    pub relative_gap: f64,
    /// True when every condition holds once Theorem 2 is judged with the tight bounds.
    pub feasible: bool,
    /// Theorem 2's torque conditions judged with both bounds.
    pub conditions: Vec<TightCondition>,
}

/// Ratios tight / paper (dimensionless).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct TightRatios {
    /// Per-axis torque bound ratio.
    pub torque: [f64; 3],
    /// `|ω_d|` bound ratio.
    pub angular_velocity: f64,
    /// `|ω̇_d|` bound ratio.
    pub angular_acceleration: f64,
}

/// The paper's certificate of a scenario ([`controller_core::certify`]: Assumption 1, Theorems
/// 1-2, Lemma 1), computed in f64 with the filters starting at zero.
///
/// Errors: the scenario's parameters are refused (named by scenario key).
pub fn scenario_certificate(scenario: &Scenario) -> Result<Certificate<f64>> {
    certificate_by(scenario, certify)
}

/// [`scenario_certificate`] with the torque set's attitude terms charged apart only
/// ([`controller_core::bounds::certify_without_joint_bound`]): the same numbers at a fraction of
/// the cost with tilt priority, for callers that read no support of the set along the rotors,
/// or that may take the Minkowski sum's larger one (a narrower airmode interval).
///
/// Errors: the scenario's parameters are refused (named by scenario key).
pub fn scenario_certificate_without_joint_bound(scenario: &Scenario) -> Result<Certificate<f64>> {
    certificate_by(
        scenario,
        controller_core::bounds::certify_without_joint_bound,
    )
}

/// The certificate of `scenario` by `certify_fn` (one of the core's two), in f64 with the
/// filters starting at zero, its refusal named by scenario key.
fn certificate_by(scenario: &Scenario, certify_fn: CertifyFn) -> Result<Certificate<f64>> {
    certify_fn(
        &scenario.vehicle(),
        &scenario.limits(),
        &scenario.gains(),
        &scenario.trajectory::<f64>().constants(),
        FilterStart::Zero,
    )
    .map_err(|e| anyhow!("{}", crate::model::scenario::describe(&e)))
}

/// The signature of the core's `certify` and `certify_without_joint_bound` in f64.
type CertifyFn = fn(
    &controller_core::Vehicle<f64>,
    &controller_core::Limits<f64>,
    &controller_core::Gains<f64>,
    &controller_core::TrajectoryConstants<f64>,
    FilterStart,
) -> Result<Certificate<f64>, controller_core::ParameterError>;

/// The tight bounds of `scenario` (the law's gains, vehicle and trajectory; the filters start at
/// zero as in Section VI; with the integral action on, its estimate's level and rate widen the
/// confining set, [`crate::bounds::tight::confining_set`]). Errors: the parameter errors of
/// [`controller_core::certify`].
///
/// The branch and bound takes seconds; each set-up's bounds are computed once per process
/// ([`crate::bounds::memo`]), so flying the same set-up again does not search again.
pub fn scenario_tight_bounds(scenario: &Scenario) -> Result<TightBounds> {
    scenario_tight_bounds_with(scenario, &TightOptions::default())
}

/// [`scenario_tight_bounds`] with the branch and bound's budget and gap of `options` (a larger
/// budget gives a bound as sound and at least as tight; `host-sim bounds --boxes`). Errors: as
/// [`scenario_tight_bounds`].
pub fn scenario_tight_bounds_with(
    scenario: &Scenario,
    options: &TightOptions,
) -> Result<TightBounds> {
    let (vehicle, gains) = (scenario.vehicle(), scenario.gains());
    let constants = scenario.trajectory::<f64>().constants();
    if gains.position.vertical.is_some()
        || gains.local.is_some()
        || gains.heading_compensator.is_some()
    {
        return certified_stand_in(scenario);
    }
    // Every input of the search, spelled exactly: the same set-up flown again reuses the bounds.
    let key = format!(
        "{vehicle:?} {gains:?} {constants:?} {:?} {options:?}",
        FilterStart::Zero
    );
    crate::bounds::memo::memoised(key, || {
        tight_bounds(&vehicle, &gains, &constants, FilterStart::Zero, options)
    })
    .map_err(|e| anyhow!("{}", crate::model::scenario::describe(&e)))
}

/// The certificate's own bounds in the tight bounds' place, for the set-ups the branch and bound
/// does not model (the vertical channel apart, docs/vertical-channel.md, the envelope
/// design's local regime, docs/envelope-design.md, and the compensated heading, controller-core's
/// `heading_compensator`): its confining set is the paper's symmetric one with one set of
/// position gains and the reference heading. Sound (they are the certified bounds, each the larger of
/// the global and the local regime's), only not tighter; `boxes` is 0, which says no search ran.
/// Errors: the certificate cannot be computed.
fn certified_stand_in(scenario: &Scenario) -> Result<TightBounds> {
    let c = scenario_certificate(scenario)?;
    let b = &c.bounds;
    let (mut w, mut a) = (b.angular_velocity, b.angular_acceleration);
    if let Some(l) = &c.local {
        w = w.max(l.bounds.angular_velocity);
        a = a.max(l.bounds.angular_acceleration);
    }
    let torque: [f64; 3] = c.torque_max_all().into();
    Ok(TightBounds {
        angular_velocity: w,
        angular_acceleration: a,
        horizontal_acceleration: a,
        yaw_acceleration: a,
        torque_max: torque,
        lower: TightLower {
            angular_velocity: 0.0,
            angular_acceleration: 0.0,
            horizontal_acceleration: 0.0,
            yaw_acceleration: 0.0,
            torque_max: [0.0; 3],
        },
        boxes: 0,
    })
}

/// What a run's samples are checked against.
pub fn tight_limits(b: &TightBounds) -> TightLimits {
    TightLimits {
        torque_max_Nm: b.torque_max,
        angular_velocity_max_rad_s: b.angular_velocity,
        angular_acceleration_max_rad_s2: b.angular_acceleration,
    }
}

/// Puts `tight` beside the paper's certificate `paper` and re-judges Theorem 2's torque
/// conditions with it.
pub fn tight_report(paper: &Certificate<f64>, tight: &TightBounds) -> TightReport {
    let b = &paper.bounds;
    let conditions: Vec<TightCondition> = paper
        .conditions
        .iter()
        .filter_map(|c| {
            let axis = THEOREM2_TORQUE.iter().position(|n| *n == c.name)?;
            let rhs_tight = tight.torque_max[axis];
            Some(TightCondition {
                name: c.name.into(),
                lhs: c.lhs,
                rhs_paper: c.rhs,
                rhs_tight,
                holds_paper: c.holds,
                holds_tight: c.lhs > rhs_tight,
            })
        })
        .collect();
    // With the integral action on, its stability conditions count too.
    let others_hold = paper
        .all_conditions()
        .filter(|c| !THEOREM2_TORQUE.contains(&c.name))
        .all(|c| c.holds);
    TightReport {
        torque_max_Nm: tight.torque_max,
        angular_velocity_max_rad_s: tight.angular_velocity,
        angular_acceleration_max_rad_s2: tight.angular_acceleration,
        ratio_to_paper: TightRatios {
            torque: std::array::from_fn(|i| tight.torque_max[i] / b.torque_max[i]),
            angular_velocity: tight.angular_velocity / b.angular_velocity,
            angular_acceleration: tight.angular_acceleration / b.angular_acceleration,
        },
        relative_gap: relative_gap(tight),
        feasible: others_hold && conditions.iter().all(|c| c.holds_tight),
        conditions,
    }
}

/// The largest relative gap `(bound − best value seen)/bound` of the branch and bound's searches
/// (`|ω_d|`, `|ω̇_d|` and the torque), dimensionless: how far its bounds might still come down.
pub fn relative_gap(b: &TightBounds) -> f64 {
    let l = &b.lower;
    let mut pairs = vec![
        (b.angular_velocity, l.angular_velocity),
        (b.angular_acceleration, l.angular_acceleration),
    ];
    pairs.extend((0..3).map(|i| (b.torque_max[i], l.torque_max[i])));
    pairs
        .into_iter()
        .map(|(upper, lower)| (upper - lower) / upper)
        .fold(0.0, f64::max)
}

/// The names of Theorem 2's per-axis torque conditions in [`controller_core::certify`], in axis
/// order.
pub const THEOREM2_TORQUE: [&str; 3] = [
    "theorem2.torque_max_roll",
    "theorem2.torque_max_pitch",
    "theorem2.torque_max_yaw",
];

/// The tight bounds a sample is checked against.
#[derive(Clone, Copy, Debug, Serialize, PartialEq)]
#[allow(non_snake_case)]
pub struct TightLimits {
    /// Per-axis bound on `|τ_i|` [N m], body frame.
    pub torque_max_Nm: [f64; 3],
    /// Bound on `|ω_d|` [rad/s].
    pub angular_velocity_max_rad_s: f64,
    /// Bound on `|ω̇_d|` [rad/s²].
    pub angular_acceleration_max_rad_s2: f64,
}

impl TightLimits {
    /// Whether a sample exceeds a bound, with the bound checks' rounding `slack` (relative).
    pub fn exceeded(&self, torque: &Vector3<f64>, w_d: f64, w_d_dot: f64, slack: f64) -> bool {
        w_d > self.angular_velocity_max_rad_s * (1.0 + slack)
            || w_d_dot > self.angular_acceleration_max_rad_s2 * (1.0 + slack)
            || (0..3).any(|i| torque[i].abs() > self.torque_max_Nm[i] * (1.0 + slack))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The paper's set-up: its yaw condition fails as written; the report keeps the paper's
    /// numbers and judges the tight bound against the same `τ_max`.
    #[test]
    fn conditions_keep_the_paper_side_and_rejudge_with_the_tight_bound() {
        let scenario = Scenario::paper();
        let paper =
            crate::bounds::certificate::scenario_certificate(&scenario).expect("paper certificate");
        let tight = scenario_tight_bounds(&scenario).expect("tight bounds");
        let r = tight_report(&paper, &tight);
        assert_eq!(r.conditions.len(), 3);
        for (i, c) in r.conditions.iter().enumerate() {
            assert_eq!(c.name, THEOREM2_TORQUE[i]);
            assert_eq!(c.rhs_paper, paper.bounds.torque_max[i]);
            assert_eq!(c.holds_tight, c.lhs > tight.torque_max[i]);
        }
        assert!(
            !r.conditions[2].holds_paper,
            "the paper's yaw condition fails as written"
        );
        for i in 0..3 {
            assert!(r.ratio_to_paper.torque[i] > 0.0 && r.ratio_to_paper.torque[i] <= 1.0);
        }
    }
}
