//! Vehicle, actuator limits and gains, with their validation.

use nalgebra::Vector3;

use crate::attitude_control::AttitudeGains;
use crate::integral::IntegralGains;
use crate::position::PositionGains;
use crate::reference::TrajectoryConstants;
use crate::scalar::{lit, to_f64, Scalar};
use crate::tilt_priority::TiltPriorityGains;
use crate::velocity_limit::VelocityLimit;

/// Rigid-body parameters of eq:FullDynamics.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vehicle<T: Scalar> {
    /// Mass `m` \[kg\].
    pub mass: T,
    /// Diagonal of the inertia `J = diag(J₁₁, J₂₂, J₃₃)` [kg m²], body frame.
    pub inertia: Vector3<T>,
    /// Gravitational acceleration `g` [m/s²].
    pub gravity: T,
}

/// Physical actuation limits `Ω_T`, `Ω_τ` (Section III).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits<T: Scalar> {
    /// Maximum thrust `T_max` \[N\].
    pub thrust_max: T,
    /// Per-axis maximum torque `τ_max` [N m], body frame.
    pub torque_max: Vector3<T>,
}

/// All controller gains (Table I).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gains<T: Scalar> {
    /// Position loop: `k_p, k_v, k_f, k_s, M_p`.
    pub position: PositionGains<T>,
    /// Attitude loop: `k_ϑ, k_ω, M_ϑ, M_ω`.
    pub attitude: AttitudeGains<T>,
    /// Hysteresis margin `δ > 0` of the MRP switch (Appendix).
    pub hysteresis: T,
    /// Memory reset threshold `α ∈ (0, 1)` of the path lifting (Appendix).
    pub reset_threshold: T,
    /// Bounded integral action (extension, docs/integral-action.md): `None` is the paper's law,
    /// bit for bit.
    pub integral: Option<IntegralGains<T>>,
    /// Per-axis attitude feedback with tilt priority (extension, docs/tilt-priority.md): `None`
    /// is the paper's radial feedback, bit for bit.
    pub tilt_priority: Option<TiltPriorityGains<T>>,
    /// Velocity-limited position feedback (extension, docs/velocity-limit.md): `None` is the
    /// paper's `ubar_p = −σ_p(k_p z₁ + k_v z₂)`, bit for bit.
    pub velocity_limit: Option<VelocityLimit<T>>,
}

impl<T: Scalar> Vehicle<T> {
    /// The quadrotor of Section VI: `m = 0.460 kg`, `J = diag(2.24, 2.9, 5.3)·10⁻³ kg m²`,
    /// `g = 9.81 m/s²` (the value that reproduces the paper's `T ∈ [3.51, 6.19] N`).
    pub fn paper() -> Self {
        Self {
            mass: lit(0.460),
            inertia: Vector3::new(lit(2.24e-3), lit(2.9e-3), lit(5.3e-3)),
            gravity: lit(9.81),
        }
    }
}

impl<T: Scalar> Limits<T> {
    /// Section VI: `T_max = 7 N`, `τ_max = (0.5, 0.5, 0.5) N m`.
    pub fn paper() -> Self {
        Self {
            thrust_max: lit(7.0),
            torque_max: Vector3::repeat(lit(0.5)),
        }
    }
}

impl<T: Scalar> Gains<T> {
    /// Table I: `k_p = 9, k_v = 6, k_f = 2, k_s = 20, k_ϑ = 100, k_ω = 0.1, M_p = 2,
    /// M_ϑ = 0.206, M_ω = 0.045, δ = 0.02, α = 0.25`; no integral action.
    pub fn paper() -> Self {
        Self {
            position: PositionGains {
                kp: lit(9.0),
                kv: lit(6.0),
                kf: lit(2.0),
                ks: lit(20.0),
                saturation: lit(2.0),
            },
            attitude: AttitudeGains {
                k_mrp: lit(100.0),
                k_omega: lit(0.1),
                mrp_saturation: lit(0.206),
                omega_saturation: lit(0.045),
            },
            hysteresis: lit(0.02),
            reset_threshold: lit(0.25),
            integral: None,
            tilt_priority: None,
            velocity_limit: None,
        }
    }
}

/// A parameter the controller refuses, with the violated requirement and its numbers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParameterError {
    /// A parameter that must be finite and `> 0` is not.
    NotPositive {
        /// Parameter name (e.g. `"k_p"`, `"mass"`).
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// A parameter outside an open interval `(low, high)`.
    OutOfRange {
        /// Parameter name.
        name: &'static str,
        /// Its value.
        value: f64,
        /// Lower end (exclusive).
        low: f64,
        /// Upper end (exclusive).
        high: f64,
    },
    /// `M_p < g − K_a3` (Section IV) is violated: the thrust could vanish or point down.
    SaturationTooLarge {
        /// `M_p` [m/s²].
        saturation: f64,
        /// `g − K_a3` [m/s²].
        limit: f64,
    },
    /// A trajectory constant is negative or not finite.
    BadTrajectoryConstant {
        /// Constant name (e.g. `"K_a3"`).
        name: &'static str,
        /// Its value.
        value: f64,
    },
}

impl core::fmt::Display for ParameterError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            Self::NotPositive { name, value } => {
                write!(f, "{name} must be finite and > 0, got {value}")
            }
            Self::OutOfRange { name, value, low, high } => {
                write!(f, "{name} must lie in ({low}, {high}), got {value}")
            }
            Self::SaturationTooLarge { saturation, limit } => write!(
                f,
                "M_p < g - K_a3 violated (Section IV): M_p = {saturation} m/s^2, g - K_a3 = {limit} m/s^2"
            ),
            Self::BadTrajectoryConstant { name, value } => {
                write!(f, "trajectory constant {name} must be finite and >= 0, got {value}")
            }
        }
    }
}

pub(crate) fn positive<T: Scalar>(name: &'static str, value: T) -> Result<(), ParameterError> {
    if value.is_finite() && value > T::zero() {
        Ok(())
    } else {
        Err(ParameterError::NotPositive {
            name,
            value: to_f64(value),
        })
    }
}

impl<T: Scalar> Vehicle<T> {
    /// Checks `m > 0`, `J_ii > 0`, `g > 0` (all finite).
    /// Errors: [`ParameterError::NotPositive`] naming the first offender.
    pub fn validate(&self) -> Result<(), ParameterError> {
        positive("mass", self.mass)?;
        for (name, j) in ["J_11", "J_22", "J_33"].iter().zip(self.inertia.iter()) {
            positive(name, *j)?;
        }
        positive("gravity", self.gravity)
    }
}

impl<T: Scalar> Limits<T> {
    /// Checks `T_max > 0` and `τ_max,i > 0` (all finite).
    /// Errors: [`ParameterError::NotPositive`] naming the first offender.
    pub fn validate(&self) -> Result<(), ParameterError> {
        positive("thrust_max", self.thrust_max)?;
        for (name, t) in ["tau_max_1", "tau_max_2", "tau_max_3"]
            .iter()
            .zip(self.torque_max.iter())
        {
            positive(name, *t)?;
        }
        Ok(())
    }
}

impl<T: Scalar> Gains<T> {
    /// The Assumption 1 constants of the reference as the law applies it: `k` itself, or with the
    /// feedforward scale on ([`crate::feedforward_scale`], extension, docs/integral-action.md)
    /// the constants of the scaled feedforward `(1 + μ_f) p̈_d`
    /// ([`crate::feedforward_scale::FeedforwardScaleGains::constants`]). Every bound of
    /// [`crate::certify`] and the controller's reference check use these.
    pub fn law_constants(&self, k: &TrajectoryConstants<T>) -> TrajectoryConstants<T> {
        match &self.integral {
            Some(IntegralGains {
                feedforward_scale: Some(f),
                bandwidth,
                ..
            }) => f.constants(k, *bandwidth),
            _ => *k,
        }
    }

    /// Checks every gain and level `> 0`, `δ > 0` and `0 < α < 1`.
    /// Errors: [`ParameterError::NotPositive`] or [`ParameterError::OutOfRange`].
    /// Source: Section IV (`k_p, k_v, k_f, k_s, M_p > 0`), Section V (`k_ϑ, k_ω, M_ϑ, M_ω > 0`),
    /// Appendix (`δ > 0`, `α ∈ (0, 1)`); with the integral action, [`IntegralGains::validate`]; with
    /// tilt priority, [`TiltPriorityGains::validate`]; with the velocity limit,
    /// [`VelocityLimit::validate`].
    pub fn validate(&self) -> Result<(), ParameterError> {
        if let Some(i) = &self.integral {
            i.validate()?;
        }
        if let Some(t) = &self.tilt_priority {
            t.validate()?;
        }
        if let Some(v) = &self.velocity_limit {
            v.validate(self.position.saturation)?;
        }
        let p = &self.position;
        let a = &self.attitude;
        for (name, v) in [
            ("k_p", p.kp),
            ("k_v", p.kv),
            ("k_f", p.kf),
            ("k_s", p.ks),
            ("M_p", p.saturation),
            ("k_theta", a.k_mrp),
            ("k_omega", a.k_omega),
            ("M_theta", a.mrp_saturation),
            ("M_omega", a.omega_saturation),
            ("delta", self.hysteresis),
        ] {
            positive(name, v)?;
        }
        let alpha = self.reset_threshold;
        if !(alpha.is_finite() && alpha > T::zero() && alpha < T::one()) {
            return Err(ParameterError::OutOfRange {
                name: "alpha",
                value: to_f64(alpha),
                low: 0.0,
                high: 1.0,
            });
        }
        Ok(())
    }
}
