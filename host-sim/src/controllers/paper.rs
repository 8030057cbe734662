//! The paper's law, `controller_core::Controller`, behind [`FlightController`].

use anyhow::{anyhow, Result};
use controller_core::scalar::{lit, to_f64, Scalar};
use controller_core::{
    ControlOutput, Controller, ReferenceSample, ReferenceTrajectory, Trajectory,
};
use nalgebra::Vector3;

use super::{Command, FlightController, SwitchCounts};
use crate::plant::RigidBodyState;
use crate::scenario::Scenario;
use crate::sim::measure;

/// `controller_core::Controller<T>` with the scenario's vehicle, gains and trajectory: samples
/// the reference at `lit(t)` and measures the state through [`measure`]. It keeps the last
/// step's reference and output, whose diagnostics the main run ([`crate::sim`]) reports.
#[derive(Clone, Debug)]
pub struct PaperLaw<T: Scalar> {
    controller: Controller<T>,
    trajectory: ReferenceTrajectory<T>,
    last: Option<(ReferenceSample<T>, ControlOutput<T>)>,
}

pub(crate) fn back3<T: Scalar>(v: &Vector3<T>) -> Vector3<f64> {
    v.map(to_f64)
}

impl<T: Scalar> PaperLaw<T> {
    /// Errors: the law refuses the scenario's parameters (named by scenario key).
    pub fn new(scenario: &Scenario) -> Result<Self> {
        let trajectory = scenario.trajectory::<T>();
        let controller = Controller::new(
            scenario.vehicle::<T>(),
            scenario.gains::<T>(),
            &trajectory.constants(),
        )
        .map_err(|e| anyhow!("{}", crate::scenario::describe(&e)))?;
        Ok(Self {
            controller,
            trajectory,
            last: None,
        })
    }

    /// The reference sample and the law's whole output (command and diagnostics) of the last
    /// [`FlightController::step`], `None` before the first.
    pub fn last_step(&self) -> Option<(&ReferenceSample<T>, &ControlOutput<T>)> {
        self.last.as_ref().map(|(r, o)| (r, o))
    }
}

impl<T: Scalar> FlightController for PaperLaw<T> {
    fn name(&self) -> &str {
        "paper"
    }

    fn step(&mut self, measured: &RigidBodyState, t: f64, dt: f64) -> Result<Command> {
        let reference = self.trajectory.sample(lit(t));
        let out = self
            .controller
            .step(&measure::<T>(measured), &reference, lit(dt))
            .map_err(|e| anyhow!("controller refused the sample at t = {t:.3} s: {e}"))?;
        let d = &out.diagnostics;
        let command = Command {
            thrust: to_f64(out.thrust),
            torque: back3(&out.torque),
            desired_rotation: d.desired_rotation.map(to_f64),
            desired_angular_velocity: back3(&d.desired_angular_velocity),
            desired_angular_acceleration: back3(&d.desired_angular_acceleration),
            switches_total: SwitchCounts {
                switches: d.jumps_total.m_flips,
                resets: d.jumps_total.q_hat_resets,
            },
        };
        self.last = Some((reference, out));
        Ok(command)
    }
}
