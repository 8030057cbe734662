//! One run with its time series kept, for the ablation and comparison plots.

use anyhow::Result;

use super::metrics::{BoundSet, Convergence, MetricsAccumulator, RunMetrics};
use crate::fly::closed_loop::fly;
use crate::fly::controllers::ControllerKind;
use crate::model::plant::RigidBodyState;
use crate::model::scenario::Scenario;

/// One sample of a traced run.
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(non_snake_case)]
pub struct TracePoint {
    /// Time \[s\].
    pub t_s: f64,
    /// `|p − p_d|` \[m\].
    pub position_error_m: f64,
    /// Attitude error against the controller's own `R_d` \[deg\].
    pub attitude_error_deg: f64,
    /// Thrust command \[N\].
    pub thrust_N: f64,
    /// `max_i |τ_i|` [N m].
    pub torque_abs_max_Nm: f64,
    /// `|ω_d|` [rad/s].
    pub omega_d_rad_s: f64,
    /// `|ω̇_d|` [rad/s²].
    pub omega_d_dot_rad_s2: f64,
    /// Switches so far.
    pub switches: u32,
}

/// Flies one run and returns its metrics and time series.
///
/// Errors: the controller cannot be built or refused a sample.
pub fn trace(
    scenario: &Scenario,
    controller: ControllerKind,
    initial: &RigidBodyState,
    seed: u64,
    convergence: Convergence,
    bounds: BoundSet,
) -> Result<(RunMetrics, Vec<TracePoint>)> {
    let sim = &scenario.simulation;
    let mut acc =
        MetricsAccumulator::new(convergence, bounds, sim.duration_s, sim.controller_period_s);
    let mut points = Vec::new();
    let mut c = controller.build(scenario)?;
    fly(scenario, c.as_mut(), initial, seed, |s| {
        acc.push(s);
        points.push(TracePoint {
            t_s: s.t,
            position_error_m: s.position_error_m,
            attitude_error_deg: s.attitude_error_rad.to_degrees(),
            thrust_N: s.command.thrust,
            torque_abs_max_Nm: s.command.torque.amax(),
            omega_d_rad_s: s.command.desired_angular_velocity.norm(),
            omega_d_dot_rad_s2: s.command.desired_angular_acceleration.norm(),
            switches: s.command.switches_total.switches,
        });
    })?;
    Ok((acc.finish(), points))
}

/// A time-series plot of a traced quantity: file name, title, y label, y scale, and the value.
pub type PanelSpec = (
    &'static str,
    &'static str,
    &'static str,
    crate::output::chart::Scale,
    fn(&TracePoint) -> f64,
);
