//! The nominal tasks every controller is judged by first: a hover, a 1 m horizontal step and a
//! 30° roll from hover at (0, 0, 5) m, 10 s each, settling as in `campaign` (5 cm and 2°,
//! staying below until the end). `compare` flies them for each contestant, and `design` scores
//! and reports them for its candidates (the same definition, so the figures agree).

use anyhow::Result;
use nalgebra::Vector3;
use serde::Serialize;

use super::Contestant;
use crate::model::plant::RigidBodyState;
use crate::model::scenario::{HeadingConfig, Scenario, TrajectoryConfig};
use crate::runs::metrics::{BoundSet, Convergence, RunMetrics};
use crate::runs::trace::trace;

/// Hover and step checks of one contestant.
#[derive(Clone, Debug, Serialize)]
pub struct SanityRow {
    /// Contestant.
    pub label: String,
    /// Hover: position error after 10 s \[m\].
    pub hover_final_position_error_m: f64,
    /// 1 m horizontal step: settling time \[s\].
    pub step_settling_time_s: Option<f64>,
    /// 1 m horizontal step: position error after 10 s \[m\].
    pub step_final_position_error_m: f64,
    /// 30° roll step: settling time \[s\].
    pub tilt_settling_time_s: Option<f64>,
    /// Tracking of the scenario's own reference (for a design, its certified helix) from the
    /// scenario's initial state over its duration: mean `|p − p_d|` over the last 5 s \[m\]
    /// ([`helix_tracking_error`]); `None` where it was not flown (the design's search).
    pub helix_tracking_error_m: Option<f64>,
}

/// Hover, 1 m step and 30° tilt from hover at (0, 0, 5) m, 10 s each, for contestant `c` on
/// `base` (its vehicle, plant, gains and controller settings; the trajectory replaced by the
/// hover); `bounds` are the bounds its samples are checked against. Errors: the controller
/// refused the scenario.
pub fn sanity(base: &Scenario, c: &Contestant, bounds: BoundSet) -> Result<SanityRow> {
    let mut s = c.scenario(base);
    s.trajectory = TrajectoryConfig::Hover {
        point_m: [0.0, 0.0, 5.0],
        heading: HeadingConfig::Constant { yaw_rad: 0.0 },
    };
    s.simulation.duration_s = 10.0;
    let conv = Convergence {
        after_s: 10.0,
        ..Convergence::default()
    };
    let at = |p: Vector3<f64>, attitude| RigidBodyState {
        position: p,
        velocity: Vector3::zeros(),
        attitude,
        angular_velocity: Vector3::zeros(),
    };
    let hover_point = Vector3::new(0.0, 0.0, 5.0);
    let level = nalgebra::UnitQuaternion::identity();
    let run = |initial: RigidBodyState| -> Result<RunMetrics> {
        Ok(trace(&s, c.controller, &initial, 0, conv, bounds)?.0)
    };
    let hover = run(at(hover_point, level))?;
    let step = run(at(hover_point + Vector3::x(), level))?;
    let tilt = run(at(
        hover_point,
        nalgebra::UnitQuaternion::from_euler_angles(30f64.to_radians(), 0.0, 0.0),
    ))?;
    Ok(SanityRow {
        label: c.label.clone(),
        hover_final_position_error_m: hover.final_position_error_m,
        step_settling_time_s: step.settling_time_s,
        step_final_position_error_m: step.final_position_error_m,
        tilt_settling_time_s: tilt.settling_time_s,
        helix_tracking_error_m: None,
    })
}

/// The scenario's own reference flown by contestant `c` on `base` from `base`'s initial state
/// for its duration (for a design's scenario: the certified helix, 30 s or the design's run
/// length), its samples checked against `bounds`: the mean `|p − p_d|` over the last 5 s \[m\],
/// once the start's transient is over. Errors: the controller refused the scenario.
pub fn helix_tracking_error(base: &Scenario, c: &Contestant, bounds: BoundSet) -> Result<f64> {
    let s = c.scenario(base);
    let conv = Convergence {
        after_s: s.simulation.duration_s,
        ..Convergence::default()
    };
    Ok(
        trace(&s, c.controller, &base.initial_state(), 0, conv, bounds)?
            .0
            .steady_position_error_m,
    )
}
