//! The local regime's own attitude law (extension, docs/envelope-design.md): near the
//! reference the attitude error is small, so a stiffer, better damped attitude feedback costs
//! the local torque set little, while the global gains stay what the global certificate affords
//! for every attitude.
//!
//! The attitude energy is a Lyapunov function of the law it is built from, whatever its gains
//! ([`crate::attitude_energy`]). So the switch measures the energy of the *local* law: the
//! local regime is entered at `E_L ≤ E_in`, inside it `E_L` does not increase under the local
//! law, and every sublevel set `{E_L ≤ c}` is forward invariant, exactly as with one law.
//! Outside the local regime nothing is assumed of `E_L`: the global certificate holds from any
//! state.

use crate::attitude_control::AttitudeGains;
use crate::parameter_error::{positive, ParameterError};
use crate::scalar::Scalar;
use crate::tilt_priority::TiltPriorityGains;

/// The attitude law the local regime flies: the paper's radial feedback with these gains, or
/// with [`Self::tilt_priority`] its per-axis variant (docs/tilt-priority.md).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LocalAttitude<T: Scalar> {
    /// `k_ϑ` [N m], `k_ω` [N m s/rad], `M_ϑ`, `M_ω` [N m] of the local law (the paper's radial
    /// terms; with tilt priority `k_ω`, `M_ω` are not used, as globally).
    pub attitude: AttitudeGains<T>,
    /// The local law's tilt-priority gains (trace weights, per-axis damping, turn-over term);
    /// `None`: the paper's radial feedback.
    pub tilt_priority: Option<TiltPriorityGains<T>>,
}

impl<T: Scalar> LocalAttitude<T> {
    /// Checks the local law's gains as `Gains::validate` checks the global ones.
    /// Errors: [`ParameterError::NotPositive`] naming `"local k_theta"`, `"local k_omega"`,
    /// `"local M_theta"`, `"local M_omega"`, or the tilt-priority gain with `"local "` before
    /// its name (`"local g_1"`, `"local k_omega_1"`, ...).
    pub fn validate(&self) -> Result<(), ParameterError> {
        let a = &self.attitude;
        for (name, v) in [
            ("local k_theta", a.k_mrp),
            ("local k_omega", a.k_omega),
            ("local M_theta", a.mrp_saturation),
            ("local M_omega", a.omega_saturation),
        ] {
            positive(name, v)?;
        }
        match &self.tilt_priority {
            None => Ok(()),
            Some(t) => t.validate().map_err(|e| match e {
                ParameterError::NotPositive { name, value } => ParameterError::NotPositive {
                    name: local_name(name),
                    value,
                },
                ParameterError::OutOfRange {
                    name,
                    value,
                    low,
                    high,
                } => ParameterError::OutOfRange {
                    name: local_name(name),
                    value,
                    low,
                    high,
                },
                other => other,
            }),
        }
    }
}

/// The name of a tilt-priority gain of the local law (`"g_1"` → `"local g_1"`).
fn local_name(name: &'static str) -> &'static str {
    match name {
        "g_1" => "local g_1",
        "g_2" => "local g_2",
        "g_3" => "local g_3",
        "k_omega_1" => "local k_omega_1",
        "k_omega_2" => "local k_omega_2",
        "k_omega_3" => "local k_omega_3",
        "M_omega_1" => "local M_omega_1",
        "M_omega_2" => "local M_omega_2",
        "M_omega_3" => "local M_omega_3",
        "turn_over_level" => "local turn_over_level",
        "turn_over_onset" => "local turn_over_onset",
        other => other,
    }
}
