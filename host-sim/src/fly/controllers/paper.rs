//! The paper's law, `controller_core::Controller`, behind [`FlightController`].

use anyhow::{anyhow, Result};
use controller_core::scalar::{lit, to_f64, Scalar};
use controller_core::{
    ControlOutput, Controller, ReferenceSample, ReferenceTrajectory, Trajectory,
};
use nalgebra::Vector3;

use super::measure;
use super::{Command, FlightController, SwitchCounts};
use crate::model::plant::RigidBodyState;
use crate::model::scenario::Scenario;

/// `controller_core::Controller<T>` with the scenario's vehicle, gains, trajectory and
/// `[controller]` thrust mode: samples
/// the reference at `lit(t)` and measures the state through [`measure`].
#[derive(Clone, Debug)]
pub struct PaperLaw<T: Scalar> {
    controller: Controller<T>,
    trajectory: ReferenceTrajectory<T>,
}

pub(crate) fn back3<T: Scalar>(v: &Vector3<T>) -> Vector3<f64> {
    v.map(to_f64)
}

impl<T: Scalar> PaperLaw<T> {
    /// Errors: the law refuses the scenario's parameters (named by scenario key).
    pub fn new(scenario: &Scenario) -> Result<Self> {
        Self::with_gains(scenario, scenario.gains::<T>())
    }

    /// [`Self::new`] with `gains` in place of the scenario's (e.g. with or without the
    /// integral action, [`controller_core::Gains::integral`]).
    ///
    /// Errors: the law refuses `gains` or the scenario's other parameters.
    pub fn with_gains(scenario: &Scenario, gains: controller_core::Gains<T>) -> Result<Self> {
        let trajectory = scenario.trajectory::<T>();
        let controller = Controller::new(scenario.vehicle::<T>(), gains, &trajectory.constants())
            .map_err(|e| anyhow!("{}", crate::model::scenario::describe(&e)))?;
        let mut controller = controller;
        let mode = scenario.thrust_mode::<T>().map_err(|e| anyhow!("{e}"))?;
        controller
            .set_thrust_mode(mode)
            .map_err(|e| anyhow!("{}", crate::model::scenario::describe(&e)))?;
        controller.set_airmode(
            scenario
                .airmode_envelope::<T>()
                .map_err(|e| anyhow!("{e}"))?,
        );
        Ok(Self {
            controller,
            trajectory,
        })
    }

    /// One sample at time `t` \[s\] from the `measured` state for a sample period `dt` \[s\]:
    /// the reference sample and the law's whole output (command and diagnostics), which the
    /// main run ([`crate::fly::sim`]) reports; [`Self::command`] turns it into the loop's command.
    ///
    /// Errors: the law refused the sample (with the time and reason).
    #[inline]
    pub fn sample(
        &mut self,
        measured: &RigidBodyState,
        t: f64,
        dt: f64,
    ) -> Result<(ReferenceSample<T>, ControlOutput<T>)> {
        let reference = self.trajectory.sample(lit(t));
        let out = self
            .controller
            .step(&measure::<T>(measured), &reference, lit(dt))
            .map_err(|e| anyhow!("controller refused the sample at t = {t:.3} s: {e}"))?;
        Ok((reference, out))
    }

    /// The loop's command (f64) from the law's output `out`.
    pub fn command(out: &ControlOutput<T>) -> Command {
        let d = &out.diagnostics;
        Command {
            thrust: to_f64(out.thrust),
            torque: back3(&out.torque),
            desired_rotation: d.desired_rotation.map(to_f64),
            desired_angular_velocity: back3(&d.desired_angular_velocity),
            desired_angular_acceleration: back3(&d.desired_angular_acceleration),
            switches_total: SwitchCounts {
                switches: d.jumps_total.m_flips,
                resets: d.jumps_total.q_hat_resets,
            },
        }
    }
}

impl<T: Scalar> FlightController for PaperLaw<T> {
    fn name(&self) -> &str {
        "paper"
    }

    fn step(&mut self, measured: &RigidBodyState, t: f64, dt: f64) -> Result<Command> {
        let (_, out) = self.sample(measured, t, dt)?;
        Ok(Self::command(&out))
    }
}
