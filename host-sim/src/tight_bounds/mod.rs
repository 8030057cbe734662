//! Tight a-priori bounds on `|ω_d|`, `|ω̇_d|` and the torque, rigorous by interval arithmetic.
//! (Soundness argument: see below.)

pub mod arith;
pub mod branch_bound;
pub mod confining_set;
pub mod desired_rates;
pub mod filter_l1;
pub mod gradient;
pub mod interval;
pub mod search;
pub mod torque;

use controller_core::{FilterStart, Gains, ParameterError, TrajectoryConstants, Vehicle};

use confining_set::ConfiningSet;
use search::{maximise, Quantity};
use torque::{torque_bound, AttitudeTerm};

/// How hard the branch and bound works.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TightOptions {
    /// Each search stops when `(upper − lower)/upper ≤ relative_gap` (dimensionless, `≥ 0`).
    pub relative_gap: f64,
    /// Safety cap on the boxes of each search; on hitting it the (still sound) upper bound of
    /// the unfinished search is returned.
    pub max_boxes: usize,
}

impl Default for TightOptions {
    /// `relative_gap = 0.01`, `max_boxes = 2 000 000`.
    fn default() -> Self {
        Self {
            relative_gap: 0.01,
            max_boxes: 2_000_000,
        }
    }
}

/// The largest values the searches saw at points of the confining boxes (same units as
/// [`TightBounds`]); they show how close the bounds are, they are not witnesses of the law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TightLower {
    /// `|ω_d|` [rad/s].
    pub angular_velocity: f64,
    /// `|ω̇_d|` [rad/s²].
    pub angular_acceleration: f64,
    /// `|(ω̇_d1, ω̇_d2)|` [rad/s²].
    pub horizontal_acceleration: f64,
    /// `|ω̇_d3|` [rad/s²].
    pub yaw_acceleration: f64,
    /// Per axis, the torque decomposition of [`torque`] at the best points [N m].
    pub torque_max: [f64; 3],
}

/// Rigorous upper bounds over the confining set (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TightBounds {
    /// `sup |ω_d|` upper bound [rad/s].
    pub angular_velocity: f64,
    /// `sup |ω̇_d|` upper bound [rad/s²].
    pub angular_acceleration: f64,
    /// `sup |(ω̇_d1, ω̇_d2)|` upper bound [rad/s²] (`H₁₂` of [`torque`]).
    pub horizontal_acceleration: f64,
    /// `sup |ω̇_d3|` upper bound [rad/s²] (`H₃` of [`torque`]).
    pub yaw_acceleration: f64,
    /// Per body axis, `sup |τ_i|` upper bound [N m].
    pub torque_max: [f64; 3],
    /// Best point values the searches saw.
    pub lower: TightLower,
    /// Boxes processed over all searches.
    pub boxes: usize,
}

/// Tight bounds for one set-up: vehicle (`J`, `g`), gains (Table I), trajectory constants
/// (Assumption 1) and the filters' start.
///
/// Errors: [`ParameterError`] for an invalid vehicle, gain or trajectory constant, for
/// `M_p ≥ g − K_a3`, or for a `relative_gap` that is negative or not finite (reported as
/// `OutOfRange { name: "relative_gap" }`).
pub fn tight_bounds(
    vehicle: &Vehicle<f64>,
    gains: &Gains<f64>,
    constants: &TrajectoryConstants<f64>,
    filter_start: FilterStart,
    options: &TightOptions,
) -> Result<TightBounds, ParameterError> {
    if !(options.relative_gap.is_finite() && options.relative_gap >= 0.0) {
        return Err(ParameterError::OutOfRange {
            name: "relative_gap",
            value: options.relative_gap,
            low: 0.0,
            high: f64::INFINITY,
        });
    }
    let set = ConfiningSet::new(vehicle, gains, constants, filter_start)?;
    let run = |q| maximise(&set, q, options.relative_gap, options.max_boxes);
    let ((w, a), (h12, h3)) = rayon::join(
        || {
            rayon::join(
                || run(Quantity::AngularVelocity),
                || run(Quantity::AngularAcceleration),
            )
        },
        || {
            rayon::join(
                || run(Quantity::HorizontalAcceleration),
                || run(Quantity::YawAcceleration),
            )
        },
    );
    // |ω̇_d|² = |(ω̇_d1, ω̇_d2)|² + ω̇_d3² ≤ H₁₂² + H₃²: a second bound, kept if smaller.
    let p = interval::Interval::point;
    let composed = (p(h12.upper).sqr() + p(h3.upper).sqr()).sqrt().hi;
    let inertia: [f64; 3] = vehicle.inertia.into();
    let mut boxes = w.boxes + a.boxes + h12.boxes + h3.boxes;
    let mut torque_max = [0.0; 3];
    let mut torque_lower = [0.0; 3];
    for axis in 0..3 {
        let term = |h: f64, y: f64| AttitudeTerm {
            axis,
            gains: gains.attitude,
            radius: 1.0 + gains.hysteresis,
            inertia: inertia[axis],
            horizontal_acceleration: h,
            yaw_acceleration: y,
        };
        // This search is cheap (3-D, no gradients): never looser than 1 %.
        let phi_gap = options.relative_gap.min(0.01);
        let phi = term(h12.upper, h3.upper).maximise(phi_gap, options.max_boxes);
        boxes += phi.boxes;
        let omega = gains.attitude.omega_saturation;
        torque_max[axis] = torque_bound(axis, omega, phi.upper, inertia, w.upper);
        let phi_low = term(h12.lower, h3.lower).maximise(phi_gap, options.max_boxes);
        torque_lower[axis] = torque_bound(axis, omega, phi_low.lower, inertia, w.lower);
    }
    Ok(TightBounds {
        angular_velocity: w.upper,
        angular_acceleration: a.upper.min(composed),
        horizontal_acceleration: h12.upper,
        yaw_acceleration: h3.upper,
        torque_max,
        lower: TightLower {
            angular_velocity: w.lower,
            angular_acceleration: a.lower,
            horizontal_acceleration: h12.lower,
            yaw_acceleration: h3.lower,
            torque_max: torque_lower,
        },
        boxes,
    })
}
