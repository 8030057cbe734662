//! Saturated hybrid position and heading tracking on SE(3), after
//! L. Martins, C. Cardeira, P. Oliveira, "Robust Global Position and Heading Tracking on SE(3)
//! via Saturated Hybrid Feedback" (the paper; equation labels in the docs are its LaTeX labels).
//!
//! `#![no_std]`, no allocation, no hardware: the same code runs on the host (f64 or f32) and on a
//! Cortex-M4F (f32). Generic over the scalar ([`Scalar`]).
//!
//! Conventions: inertial frame z up, gravity `−g e₃`; body-to-inertial Hamilton quaternions;
//! body-frame angular velocity; SI units (N, N m, rad, rad/s, m, s).
//!
//! Modules, one concept each: [`saturation`] (Definition 1), [`position`] (Section IV),
//! [`position_saturation`] (the shape of `σ_p`: the paper's componentwise one or a norm one, an
//! extension: docs/position-saturation.md),
//! [`desired_attitude`] (eq:DesiredRotationMatrix, Lemma 1), [`mrp`] (Section II),
//! [`desired_frame_bounds`] (Lemma 1 per axis of the desired frame, an extension:
//! docs/airmode.md), [`heading_compensator`] (a compensated heading fed to
//! eq:DesiredRotationMatrix so that the desired frame's yaw rate is the compensator's alone, an
//! extension of Lemma 1: docs/heading-compensator.md), [`path_lifting`] (Appendix), [`attitude_control`] (Section V), [`reference`](mod@reference)
//! (Assumption 1's trajectories), [`bounds`] (Assumption 1, Theorems 1–2, Lemma 1),
//! [`integral`], [`disturbance_observer`], [`feedforward_scale`] and [`integral_stability`]
//! (bounded integral action, an extension: docs/integral-action.md),
//! [`gains`], [`vehicle`] and [`parameter_error`] (the parameter sets and their validation),
//! [`condition`] (one inequality of a certificate), [`clamped_estimate`] (the rate-limited
//! estimates of the integral action), [`thrust`] (the paper's `T = m|u|` or the no-dive projection),
//! [`tilt_priority`] (per-axis attitude feedback levels, an extension: docs/tilt-priority.md),
//! [`lemma1_form`] (the paper's Lemma 1 or its tangential form, an extension:
//! docs/tangential-lemma1.md), [`local_regime`] (the envelope design's fast local position gains
//! on an invariant set of the attitude energy, an extension: docs/envelope-design.md), [`velocity_limit`] (a braking profile in the position feedback, an extension:
//! docs/velocity-limit.md), [`waypoint_path`] (a reference through a mission's stops with
//! closed-form Assumption 1 constants, so a mission is certified before it is flown), and
//! [`rotor_envelope`] (the rotors' `(T, τ)` set, its shadow and airmode's thrust, an extension:
//! docs/airmode.md), and [`controller`] which composes them.
#![cfg_attr(not(test), no_std)]
#![deny(missing_docs)]

pub mod attitude_control;
pub mod attitude_energy;
pub mod bounds;
pub mod clamped_estimate;
pub mod condition;
pub mod controller;
pub mod desired_attitude;
pub mod desired_frame_bounds;
pub mod disturbance_observer;
pub mod feedforward_scale;
pub mod gains;
pub mod heading_compensator;
pub mod integral;
pub mod integral_stability;
pub mod lemma1_form;
pub mod local_regime;
pub mod mrp;
pub mod parameter_error;
pub mod path_lifting;
pub mod position;
pub mod position_saturation;
pub mod reference;
pub mod rotor_envelope;
pub mod saturation;
pub mod scalar;
pub mod thrust;
pub mod tilt_priority;
pub mod torque_set;
pub mod trig;
pub mod turn_over;
pub mod vehicle;
pub mod velocity_limit;
pub mod vertical_channel;
pub mod waypoint_path;

/// The parameter types under the path they had before the split into [`gains`], [`vehicle`] and
/// [`parameter_error`] (kept for the firmware and the host tools that import them from here).
pub mod params {
    pub use crate::gains::Gains;
    pub use crate::parameter_error::ParameterError;
    pub use crate::vehicle::{Limits, Vehicle};
}

pub use bounds::{
    certify, Bounds, Certificate, Condition, FilterStart, IntegralCertificate, Violation,
};
pub use controller::{ControlOutput, Controller, Diagnostics, StepError, VehicleState};
pub use disturbance_observer::ObserverGains;
pub use feedforward_scale::{FeedforwardScaleGains, FeedforwardScaleState};
pub use gains::Gains;
pub use heading_compensator::HeadingCompensatorGains;
pub use integral::{IntegralGains, IntegralState};
pub use lemma1_form::Lemma1Form;
pub use local_regime::{LocalAttitude, LocalGains, Regime};
pub use parameter_error::ParameterError;
pub use path_lifting::JumpCounters;
pub use position_saturation::PositionSaturation;
pub use reference::{
    HeadingProfile, ReferenceSample, ReferenceTrajectory, Trajectory, TrajectoryConstants,
};
pub use rotor_envelope::RotorEnvelope;
pub use scalar::Scalar;
pub use thrust::ThrustMode;
pub use tilt_priority::TiltPriorityGains;
pub use torque_set::TorqueSet;
pub use turn_over::TurnOver;
pub use vehicle::{Limits, Vehicle};
pub use velocity_limit::{VelocityLimit, VerticalBraking};
pub use vertical_channel::VerticalChannel;
