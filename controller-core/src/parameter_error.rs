//! The error a refused parameter produces, with the violated requirement and its numbers, and the
//! positivity check every parameter set shares.

use crate::scalar::{to_f64, Scalar};

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
