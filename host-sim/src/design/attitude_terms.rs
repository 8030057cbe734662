//! The attitude terms of tilt priority's torque, sampled together along one direction: how much
//! of a rotor pair's range the certified set charges them, against what they ask at once.
//!
//! The certified torque set (docs/torque-set.md) is a Minkowski sum: the radial MRP term's ball,
//! the trace term's ball and disks and the turn-over term's box each enter at their own largest
//! value along a direction `d`. But all three are functions of the same lifted MRP error `ϑ̃`:
//! the trace term is small near the half turn, where the turn-over term acts, and the turn-over
//! term's roll and yaw bounds are not reached at one attitude. Their joint torque
//! `A(ϑ̃) = −(1 + |ϑ̃|²)/4 · s_ϑ(k_ϑ ϑ̃) − ½ vee(G R̃ − R̃ᵀG) + τ_t(ϑ̃)` can ask far less of a
//! rotor pair than the sum of the three. This module *measures* that: the largest `dᵀA(ϑ̃)` on a
//! grid of the flow set `|ϑ̃| ≤ 1 + δ`. A sample is a lower bound of the joint support, never a
//! certified upper one: nothing here enters a certificate, the fit or the firmware's gate. It is
//! reported beside the certified joint bound the set does use
//! (`controller_core::torque_set::attitude_joint`), so the bound's slack is visible.

use nalgebra::Vector3;
use serde::Serialize;

use controller_core::mrp::rotation_from_mrp;
use controller_core::torque_set::TorqueSet;
use controller_core::Gains;

/// What the attitude terms ask along one direction `d` (a rotor pair's row, [N per N m]).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct AttitudeTermsSample {
    /// The largest `dᵀA(ϑ̃)` found on the grid \[N\]: what the three terms ask at once (a lower
    /// bound of their joint support).
    pub sampled_n: f64,
    /// What the certified set charges them along `d` \[N\]: its feedback ball and disks
    /// ([`TorqueSet::support_parts`]) and the turn-over bounds' share of its box,
    /// `Σ_i |d_i| t_i`.
    pub charged_n: f64,
    /// The certified joint bound of the three along `d` \[N\]
    /// ([`controller_core::torque_set::AttitudeJoint::support`]): between the sample and the
    /// charge; `None` when the set has none (`g₁ ≠ g₂`).
    pub joint_bound_n: Option<f64>,
    /// The lifted MRP error where the sample peaked (dimensionless).
    pub at_mrp: [f64; 3],
    /// Grid points per half axis of the cube `[−(1 + δ), 1 + δ]³` the sample took.
    pub points_per_half_axis: usize,
}

/// Samples tilt priority's attitude terms (radial MRP, trace, turn-over; no damping, no
/// feedforward) along `direction` on a cubic grid of `points_per_half_axis` points per half
/// axis over the flow set `|ϑ̃| ≤ 1 + δ`, the points outside it taken radially onto its
/// boundary; `set` is the certified torque set of `gains`, which gives the charge. `None` for the
/// paper's law (its only attitude term is the ball, whose support the set already charges
/// exactly) or with no grid points. No errors. Source: extension (docs/tilt-priority.md, docs/turn-over.md, docs/torque-set.md).
pub fn sample_attitude_terms(
    gains: &Gains<f64>,
    set: &TorqueSet<f64>,
    direction: &Vector3<f64>,
    points_per_half_axis: usize,
) -> Option<AttitudeTermsSample> {
    let tilt = gains.tilt_priority.as_ref()?;
    if points_per_half_axis == 0 {
        return None;
    }
    let radius = 1.0 + gains.hysteresis;
    let n = points_per_half_axis as i64;
    let step = radius / n as f64;
    let zero = Vector3::zeros();
    let unit_inertia = Vector3::repeat(1.0);
    let mut best = (f64::NEG_INFINITY, zero);
    for i in -n..=n {
        for j in -n..=n {
            for k in -n..=n {
                let mut mrp = Vector3::new(i as f64, j as f64, k as f64) * step;
                // Points outside the flow set are taken onto its boundary sphere, where the
                // turn-over term peaks: the boundary is sampled as densely as the inside.
                let norm = mrp.norm();
                if norm > radius {
                    mrp *= radius / norm;
                }
                // ω = ω_d = ω̇_d = 0: the damping and the feedforward vanish, the attitude
                // terms are what is left of the law.
                let out = tilt.evaluate(
                    &gains.attitude,
                    &mrp,
                    &zero,
                    &rotation_from_mrp(&mrp),
                    &zero,
                    &zero,
                    &unit_inertia,
                );
                let v = direction.dot(&out.torque);
                if v > best.0 {
                    best = (v, mrp);
                }
            }
        }
    }
    let parts = set.support_parts(direction);
    let turn_over = direction
        .abs()
        .dot(&tilt.turn_over_bounds(gains.hysteresis));
    Some(AttitudeTermsSample {
        sampled_n: best.0,
        charged_n: parts.feedback_ball + parts.feedback_disks + turn_over,
        joint_bound_n: set.attitude_joint.map(|j| j.support(direction)),
        at_mrp: best.1.into(),
        points_per_half_axis,
    })
}

#[cfg(test)]
mod tests;
