//! What goes into and comes out of one controller step: the measured state, the command, the
//! diagnostics for logs and plots, and why a step is refused.

use nalgebra::{Matrix3, UnitQuaternion, Vector3};

use crate::desired_attitude::DesiredAttitudeError;
use crate::path_lifting::JumpCounters;
use crate::scalar::Scalar;

/// The measured rigid-body state `x = (p, v, R, ω)` of Problem 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VehicleState<T: Scalar> {
    /// Position `p` \[m\], inertial (z up).
    pub position: Vector3<T>,
    /// Velocity `v` [m/s], inertial.
    pub velocity: Vector3<T>,
    /// Attitude: body-to-inertial unit quaternion (Hamilton).
    pub attitude: UnitQuaternion<T>,
    /// Angular velocity `ω` [rad/s], body frame.
    pub angular_velocity: Vector3<T>,
}

/// Everything the step computed, for logs and plots (frames as noted).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Diagnostics<T: Scalar> {
    /// `z₁` \[m\], inertial (eq:Zcoordinates).
    pub z1: Vector3<T>,
    /// `z₂` [m/s], inertial.
    pub z2: Vector3<T>,
    /// `ubar_p` [m/s²], inertial.
    pub ubar_p: Vector3<T>,
    /// Filter state `u_f` at the sample [m/s²], inertial.
    pub u_f: Vector3<T>,
    /// Filter state `u_s` at the sample [m/s²], inertial.
    pub u_s: Vector3<T>,
    /// Filtered integral estimate `η_f` applied at the sample [m/s²], inertial (zero when the
    /// integral action is off; extension, docs/integral-action.md).
    pub integral: Vector3<T>,
    /// Filtered feedforward scale `μ_f` applied at the sample (dimensionless; zero when it is
    /// off; extension, [`crate::feedforward_scale`]).
    pub feedforward_scale: T,
    /// Control vector `u` [m/s²], inertial.
    pub u: Vector3<T>,
    /// Thrust direction `ρ = u/|u|`, inertial.
    pub thrust_direction: Vector3<T>,
    /// Desired attitude `R_d` (desired body to inertial).
    pub desired_rotation: Matrix3<T>,
    /// `ω_d` [rad/s], desired body frame.
    pub desired_angular_velocity: Vector3<T>,
    /// `ω̇_d` [rad/s²], desired body frame.
    pub desired_angular_acceleration: Vector3<T>,
    /// MRP attitude error `ϑ̃` (dimensionless), `|ϑ̃| ≤ 1 + δ`.
    pub mrp_error: Vector3<T>,
    /// Angular velocity error `ω̃ = ω − R̃ᵀω_d` [rad/s], body frame.
    pub omega_error: Vector3<T>,
    /// `s_ϑ(k_ϑ ϑ̃)` [N m], body.
    pub s_mrp: Vector3<T>,
    /// `s_ω(k_ω ω̃)` [N m], body.
    pub s_omega: Vector3<T>,
    /// Feedforward `τ_c` [N m], body.
    pub feedforward: Vector3<T>,
    /// Airmode's move of the collective thrust \[N\]: the thrust applied minus the thrust mode's
    /// (zero without airmode, and wherever the law's `(T, τ)` already fits the rotors;
    /// [`crate::RotorEnvelope::airmode_thrust`]).
    pub airmode_shift: T,
    /// The envelope design's regime this sample flew ([`crate::local_regime`]; `Global`
    /// without it).
    pub regime: crate::local_regime::Regime,
    /// The attitude energy `½ω̃ᵀJω̃ + Ψ(ϑ̃)` \[J\] of this sample (with tilt priority plus its trace
    /// potential; [`crate::attitude_energy::attitude_energy`]), zero without the envelope design;
    /// the local regime's own attitude law's energy where it has one ([`crate::LocalAttitude`]:
    /// what its switch measures).
    pub attitude_energy: T,
    /// Path-lifting jumps applied at this sample.
    pub jumps: JumpCounters,
    /// Path-lifting jumps since construction.
    pub jumps_total: JumpCounters,
}

/// The command of one sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ControlOutput<T: Scalar> {
    /// Collective thrust \[N\] along the body z axis: `T = m|u|`, or as set by
    /// [`crate::Controller::set_thrust_mode`], moved by airmode when it is on
    /// ([`crate::Controller::set_airmode`]).
    pub thrust: T,
    /// Torque `τ` [N m], body frame.
    pub torque: Vector3<T>,
    /// Intermediate signals.
    pub diagnostics: Diagnostics<T>,
}

/// Why a step was refused. The controller's state is unchanged when a step fails.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StepError {
    /// A measured or reference value is NaN or infinite; names the field.
    NonFiniteInput {
        /// The offending field (e.g. `"state.position"`).
        field: &'static str,
    },
    /// `dt` is not finite and positive.
    BadTimeStep {
        /// The value given \[s\].
        dt: f64,
    },
    /// The desired attitude is undefined for this reference (see [`DesiredAttitudeError`]).
    DesiredAttitude(DesiredAttitudeError),
    /// The law produced a non-finite value (defensive; not expected for finite inputs).
    NonFiniteOutput,
}

impl core::fmt::Display for StepError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::NonFiniteInput { field } => write!(f, "non-finite input: {field}"),
            Self::BadTimeStep { dt } => write!(f, "time step must be finite and > 0 s, got {dt}"),
            Self::DesiredAttitude(e) => write!(f, "desired attitude undefined: {e:?}"),
            Self::NonFiniteOutput => write!(f, "non-finite controller output"),
        }
    }
}
