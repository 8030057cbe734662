//! The vehicle's rigid-body parameters (eq:FullDynamics) and its actuation limits (Section III),
//! with their validation.

use nalgebra::Vector3;

use crate::parameter_error::{positive, ParameterError};
use crate::scalar::{lit, Scalar};

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
