//! The closed loop for any [`FlightController`], with the perturbations of the scenario's
//! `[perturbations]` table: sample (noisy measurement) → command → optional clipping →
//! disturbances → plant (RK4, optional motor lag) over the controller period.
//!
//! With the paper's law ([`crate::controllers::paper::PaperLaw`]) and no perturbation this is
//! the loop of [`crate::sim::run`] step for step (same sample times, same measurement, same
//! hold, same RK4 substeps); a test pins the commands bit for bit.

use anyhow::{anyhow, Result};
use controller_core::Trajectory;
use nalgebra::Vector3;

use crate::controllers::{Command, FlightController};
use crate::perturbation::Perturber;
use crate::plant::{PlantInput, RigidBodyState};
use crate::scenario::Scenario;
use crate::so3::rotation_angle;

/// What the loop shows its observer at every controller sample.
#[derive(Clone, Copy, Debug)]
pub struct LoopSample<'a> {
    /// Sample index.
    pub k: u64,
    /// Time \[s\].
    pub t: f64,
    /// The true plant state (not the measurement).
    pub state: &'a RigidBodyState,
    /// Reference position \[m\], inertial.
    pub reference_position: Vector3<f64>,
    /// The controller's command (before clipping).
    pub command: &'a Command,
    /// `|p − p_d|` \[m\] (true state).
    pub position_error_m: f64,
    /// Angle of `R_dᵀR` \[rad\] (true attitude against the controller's own `R_d`), in `[0, π]`.
    pub attitude_error_rad: f64,
}

/// Flies `scenario` from `initial` with `controller` for `simulation.duration_s`, drawing the
/// perturbations from `seed`, and calls `observe` at every sample. Returns the final state.
///
/// Errors: the scenario's perturbations are invalid, or the controller refused a sample (with
/// the time and reason).
pub fn fly(
    scenario: &Scenario,
    controller: &mut dyn FlightController,
    initial: &RigidBodyState,
    seed: u64,
    mut observe: impl FnMut(&LoopSample<'_>),
) -> Result<RigidBodyState> {
    scenario
        .perturbations
        .validate()
        .map_err(|e| anyhow!("{e}"))?;
    let sim = &scenario.simulation;
    let limits = scenario.limits::<f64>();
    let trajectory = scenario.trajectory::<f64>();
    let mut perturber = Perturber::new(&scenario.perturbations, seed);
    let plant = perturber.plant(&scenario.plant());
    let dt = sim.controller_period_s;
    let steps = (sim.duration_s / dt).round() as u64;
    let mut state = *initial;
    for k in 0..=steps {
        let t = k as f64 * dt;
        let measured = perturber.measure(&state);
        let command = controller.step(&measured, t, dt)?;
        let reference = trajectory.sample(t);
        let rotation = state.attitude.to_rotation_matrix().into_inner();
        observe(&LoopSample {
            k,
            t,
            state: &state,
            reference_position: reference.position,
            command: &command,
            position_error_m: (state.position - reference.position).norm(),
            attitude_error_rad: rotation_angle(&(command.desired_rotation.transpose() * rotation)),
        });
        if k == steps {
            break;
        }
        let mut input = PlantInput {
            thrust: command.thrust,
            torque: command.torque,
            ..Default::default()
        };
        if sim.clip_to_limits {
            input.thrust = command.thrust.clamp(0.0, limits.thrust_max);
            input.torque = command
                .torque
                .zip_map(&limits.torque_max, |t, m| t.clamp(-m, m));
        }
        perturber.disturb(&mut input, dt);
        state = perturber.advance(&plant, &state, &input, dt, sim.plant_step_s);
    }
    Ok(state)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::controllers::paper::PaperLaw;

    /// With the paper's law and no perturbation, the commands equal `sim::run`'s bit for bit.
    #[test]
    fn nominal_paper_loop_matches_sim_run() {
        let mut scenario = Scenario::paper();
        scenario.simulation.duration_s = 6.0;
        let (_, records) = crate::sim::run(&scenario).unwrap();
        let mut law = PaperLaw::<f32>::new(&scenario).unwrap();
        let mut k = 0;
        fly(&scenario, &mut law, &scenario.initial_state(), 99, |s| {
            let r = &records[s.k as usize];
            assert_eq!(s.command.thrust, r.thrust_N, "thrust at t = {}", s.t);
            assert_eq!(s.command.torque.x, r.torque_x_Nm);
            assert_eq!(s.command.torque.z, r.torque_z_Nm);
            assert_eq!(s.state.position.x, r.x_m);
            k += 1;
        })
        .unwrap();
        assert_eq!(k, records.len());
    }
}
