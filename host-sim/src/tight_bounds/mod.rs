//! PLACEHOLDER (integration stub, replaced by the real module at merge).
#![allow(missing_docs)]
use controller_core::bounds::{certify, FilterStart};
use controller_core::params::{Gains, Limits, ParameterError, Vehicle};
use controller_core::reference::TrajectoryConstants;

#[derive(Clone, Copy, Debug)]
pub struct TightOptions {
    pub relative_gap: f64,
    pub max_boxes: usize,
}
impl Default for TightOptions {
    fn default() -> Self {
        Self {
            relative_gap: 0.01,
            max_boxes: 1_000_000,
        }
    }
}
#[derive(Clone, Copy, Debug)]
pub struct TightBounds {
    pub angular_velocity: f64,
    pub angular_acceleration: f64,
    pub torque_max: [f64; 3],
    pub relative_gap: f64,
    pub boxes: usize,
}
pub fn tight_bounds(
    vehicle: &Vehicle<f64>,
    gains: &Gains<f64>,
    constants: &TrajectoryConstants<f64>,
    filter_start: FilterStart,
    _options: &TightOptions,
) -> Result<TightBounds, ParameterError> {
    let limits = Limits {
        thrust_max: 1e9,
        torque_max: nalgebra::Vector3::repeat(1e9),
    };
    let c = certify(vehicle, &limits, gains, constants, filter_start)?;
    Ok(TightBounds {
        angular_velocity: c.bounds.angular_velocity * 0.6,
        angular_acceleration: c.bounds.angular_acceleration * 0.45,
        torque_max: (c.bounds.torque_max * 0.6).into(),
        relative_gap: 0.0,
        boxes: 0,
    })
}
