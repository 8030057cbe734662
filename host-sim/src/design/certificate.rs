//! The certificate of a design, from the two functions the firmware trusts:
//! `controller_core::bounds::certify` (Assumption 1, Theorem 1, Lemma 1, Theorem 2) and
//! `firmware::mixer::Mixer::box_fit` (the certified `(T, τ)` box inside the rotor range).
//!
//! The actuator limits the conditions are evaluated against are what the rotor set delivers:
//! `T_max = Σ_k f_max` and `τ_max,i` = the box fit's per-axis torque capacity over the certified
//! thrust interval (the largest `|τ_i|` realisable at both thrust ends with the other torques at
//! their box bounds).

use anyhow::{anyhow, Result};
use controller_core::{
    certify, Certificate, FilterStart, Gains, Limits, TrajectoryConstants, Vehicle,
};
use firmware::config::RotorConfig;
use firmware::mixer::{BoxFit, Mixer};
use nalgebra::Vector3;

use super::authority::{box_margin, RotorSet};

/// A set-up checked by `certify` and `box_fit`.
#[derive(Clone, Debug)]
pub struct Certified {
    /// The limits derived from the rotor set \[N\], [N m].
    pub limits: Limits<f64>,
    /// `certify` with those limits.
    pub certificate: Certificate<f64>,
    /// `box_fit` of the certified box on the vehicle's rotor range.
    pub box_fit: BoxFit,
    /// `box_fit` of the certified box on the range shrunk by the requested margin at both ends.
    pub fits_with_margin: bool,
    /// Smallest headroom over rotors and corners, fraction of the rotor range.
    pub margin: f64,
}

impl Certified {
    /// Every condition holds and the box fits with the margin.
    pub fn ok(&self) -> bool {
        self.certificate.require_feasible().is_ok() && self.box_fit.fits && self.fits_with_margin
    }
}

/// The rotor set with its range shrunk by `margin` (fraction) at both ends.
pub fn shrunk_rotors(rotors: &RotorConfig, margin: f64) -> RotorConfig {
    let span = rotors.thrust_max - rotors.thrust_min;
    let m = (margin as f32) * span;
    RotorConfig {
        thrust_min: rotors.thrust_min + m,
        thrust_max: rotors.thrust_max - m,
        ..*rotors
    }
}

/// Certifies `gains` for `vehicle` on `rotors` with reference `constants`.
///
/// Errors: `certify` refuses the parameters (e.g. a limit of zero when the box leaves no torque
/// capacity), or the mixer cannot be built.
pub fn certify_design(
    vehicle: &Vehicle<f64>,
    rotors: &RotorConfig,
    gains: &Gains<f64>,
    constants: &TrajectoryConstants<f64>,
    margin: f64,
) -> Result<Certified> {
    let mixer = Mixer::new(rotors).map_err(|e| anyhow!("rotor set refused by the mixer: {e:?}"))?;
    let set = RotorSet::new(rotors).map_err(|e| anyhow!("rotor set: {e}"))?;
    // First pass: the bounds (they do not depend on the limits).
    let probe = Limits {
        thrust_max: set.thrust_total_max(),
        torque_max: Vector3::repeat(1.0),
    };
    let first = certify(vehicle, &probe, gains, constants, FilterStart::Zero)
        .map_err(|e| anyhow!("{}", crate::scenario::describe(&e)))?;
    let b = &first.bounds;
    let tau32 = b.torque_max.map(|x| x as f32);
    let fit = mixer.box_fit(b.thrust_min as f32, b.thrust_max as f32, &tau32);
    let capacity = Vector3::from(fit.torque_capacity.map(f64::from));
    // A zero capacity is a limit `certify` refuses; keep it positive and let the condition fail.
    let limits = Limits {
        thrust_max: set.thrust_total_max(),
        torque_max: capacity.map(|c| c.max(1e-12)),
    };
    let certificate = certify(vehicle, &limits, gains, constants, FilterStart::Zero)
        .map_err(|e| anyhow!("{}", crate::scenario::describe(&e)))?;
    let shrunk = Mixer::new(&shrunk_rotors(rotors, margin))
        .map_err(|e| anyhow!("rotor range shrunk by the margin {margin}: {e:?}"))?;
    let fits_with_margin = shrunk
        .box_fit(b.thrust_min as f32, b.thrust_max as f32, &tau32)
        .fits;
    Ok(Certified {
        limits,
        certificate,
        box_fit: fit,
        fits_with_margin,
        margin: box_margin(&set, (b.thrust_min, b.thrust_max), &b.torque_max),
    })
}
