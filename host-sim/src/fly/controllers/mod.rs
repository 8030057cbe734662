//! Controllers that fly the same closed loop ([`crate::fly::closed_loop`]): the paper's law and the
//! baselines it is compared with.
//!
//! - [`paper::PaperLaw`]: `controller_core::Controller` itself (f32 or f64), unchanged;
//! - [`ablated::AblatedLaw`]: the same composition with one design choice removed (memoryless
//!   `q₀ ≥ 0` lifting, or no output filters), for the ablations;
//! - [`lee::LeeGeometric`]: Lee, Leok and McClamroch (2010), geometric tracking on SE(3);
//! - [`px4_cascade::Px4Cascade`]: a PX4-style cascade (position P → velocity PID → tilt-limited
//!   thrust vector → quaternion attitude P with the memoryless `w ≥ 0` sign → rate PID).
//!
//! Every controller samples its reference itself (it owns a copy of the scenario's trajectory),
//! receives the measured state in f64 and returns a [`Command`] in f64.

pub mod ablated;
pub mod lee;
pub mod paper;
pub mod px4_cascade;

use anyhow::Result;
use controller_core::scalar::{lit, Scalar};
use controller_core::VehicleState;
use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use crate::model::plant::RigidBodyState;
use crate::model::scenario::Scenario;

/// The plant state (true, or as measured with the scenario's noise) in the controller's
/// scalar `T`: what `controller_core::Controller::step` takes. The attitude is renormalised
/// after the cast.
pub fn measure<T: Scalar>(s: &RigidBodyState) -> VehicleState<T> {
    VehicleState {
        position: s.position.map(lit),
        velocity: s.velocity.map(lit),
        attitude: UnitQuaternion::new_normalize(s.attitude.quaternion().cast::<T>()),
        angular_velocity: s.angular_velocity.map(lit),
    }
}

/// Discontinuities of the attitude-error representation since the start of the run.
///
/// `switches` counts the jumps of the error the feedback sees (the paper's MRP flips between
/// principal and shadow MRP; the memoryless `q₀ ≥ 0` / `w ≥ 0` choices' hemisphere changes);
/// these are what chatters under noise near 180°. `resets` counts the paper's memory-quaternion
/// resets, which do not change the feedback (its output is continuous across them).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct SwitchCounts {
    /// Jumps of the attitude error fed back (chattering when frequent).
    pub switches: u32,
    /// Memory resets that leave the fed-back error unchanged (paper's `q̂` resets).
    pub resets: u32,
}

/// One sample's command and what the comparison needs to know about it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Command {
    /// Collective thrust \[N\] along body z (not clipped).
    pub thrust: f64,
    /// Torque [N m], body frame (not clipped).
    pub torque: Vector3<f64>,
    /// The desired attitude this controller tracks at the sample (desired body to inertial).
    pub desired_rotation: Matrix3<f64>,
    /// Desired angular velocity [rad/s], desired body frame (zero when the controller has none).
    pub desired_angular_velocity: Vector3<f64>,
    /// Desired angular acceleration [rad/s²], desired body frame (zero when it has none).
    pub desired_angular_acceleration: Vector3<f64>,
    /// Switch counts since the start of the run (after this sample).
    pub switches_total: SwitchCounts,
}

/// A sampled flight controller: the closed loop calls [`FlightController::step`] every
/// controller period and holds the command until the next call.
pub trait FlightController: Send {
    /// Short name used in reports (`"paper"`, `"lee"`, `"px4"`, …).
    fn name(&self) -> &str;
    /// The command at time `t` \[s\] from the measured state, for a sample period `dt` \[s\].
    ///
    /// Errors: the controller refused the sample (e.g. a non-finite measurement), with the reason.
    fn step(&mut self, measured: &RigidBodyState, t: f64, dt: f64) -> Result<Command>;
}

/// Which controller a run uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ControllerKind {
    /// The paper's saturated hybrid law (controller-core), at the scenario's precision.
    Paper,
    /// Lee, Leok, McClamroch (2010) geometric SE(3) controller.
    Lee,
    /// PX4-style cascade.
    Px4,
    /// Ablation: the paper's law with the memoryless `q₀ ≥ 0` lifting (no hysteresis, no memory);
    /// always f64.
    PaperMemoryless,
    /// Ablation: the paper's law without the two output filters; always f64.
    PaperNoFilter,
}

impl ControllerKind {
    /// The name used in reports and file names.
    pub fn label(self) -> &'static str {
        match self {
            Self::Paper => "paper",
            Self::Lee => "lee",
            Self::Px4 => "px4",
            Self::PaperMemoryless => "paper_memoryless",
            Self::PaperNoFilter => "paper_no_filter",
        }
    }

    /// Builds the controller for `scenario`.
    ///
    /// Errors: the scenario's parameters are refused by the controller (named by scenario key).
    pub fn build(self, scenario: &Scenario) -> Result<Box<dyn FlightController>> {
        use crate::model::scenario::Precision;
        Ok(match (self, scenario.simulation.precision) {
            (Self::Paper, Precision::F32) => Box::new(paper::PaperLaw::<f32>::new(scenario)?),
            (Self::Paper, Precision::F64) => Box::new(paper::PaperLaw::<f64>::new(scenario)?),
            (Self::Lee, _) => Box::new(lee::LeeGeometric::new(
                scenario,
                lee::LeeGains::scaled_from_paper(scenario),
            )),
            (Self::Px4, _) => Box::new(px4_cascade::Px4Cascade::new(
                scenario,
                px4_cascade::Px4Gains::defaults(),
            )),
            (Self::PaperMemoryless, _) => Box::new(ablated::AblatedLaw::<f64>::new(
                scenario,
                ablated::Ablation {
                    lifting: ablated::Lifting::Memoryless,
                    filters: true,
                },
            )?),
            (Self::PaperNoFilter, _) => Box::new(ablated::AblatedLaw::<f64>::new(
                scenario,
                ablated::Ablation {
                    lifting: ablated::Lifting::Hybrid,
                    filters: false,
                },
            )?),
        })
    }
}
