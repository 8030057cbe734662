//! The certification gate: a set-up (vehicle, limits, gains, a reference's Assumption 1
//! constants) is flown only if every condition of the a-priori bound certificate holds
//! (Assumption 1, Theorem 1, Lemma 1 and Theorem 2) and the certified `(T, τ)` set
//! `[T_lo, T_hi] × S` fits inside the rotors with the configured margin (`S` the torque set of
//! Theorem 2's terms, [`controller_core::TorqueSet`]: inside the box `Π[−τ_i, τ_i]` of its
//! per-axis bounds, so every box that fitted still fits), with
//! `[T_lo, T_hi]` the configured thrust's interval (Theorem 1's `[T_min, T_max]` for the paper's
//! `T = m|u|`, `[T_floor, T_max]` for the no-dive thrust; [`ThrustChoice::interval`])
//! ([`crate::mixer::Mixer::set_margin`]). Pure functions, so the boot report, the arm check and
//! every reference change apply the very same test.

pub use crate::gate_failure::GateFailure;
use controller_core::Certificate;

use crate::config::ThrustChoice;
use crate::mixer::Mixer;

/// Name of the rotor-fit "condition" in refusals and events: `lhs` is the certified set's
/// smallest headroom, `rhs` the required margin (fractions of the rotor thrust range).
pub const ROTOR_FIT: &str = "rotor_fit.margin";

/// Name of the thrust-floor "condition": `lhs` is the floor, `rhs` Theorem 1's `T_min` \[N\]
/// (a floor above it would raise the thrust above the paper's).
pub const THRUST_FLOOR: &str = "thrust_floor";

/// The thrust interval `[T_lo, T_hi]` \[N\] of `thrust` for `certificate`'s bounds, or the
/// failure [`THRUST_FLOOR`] when its floor is above `T_min`.
pub fn thrust_interval(
    certificate: &Certificate<f32>,
    thrust: &ThrustChoice,
) -> Result<(f32, f32), GateFailure> {
    let b = &certificate.bounds;
    thrust.interval(b).map_err(|_| GateFailure {
        condition: THRUST_FLOOR,
        lhs: match *thrust {
            ThrustChoice::VerticalPriority { floor, .. } => floor,
            ThrustChoice::Norm => f32::NAN,
        },
        rhs: b.thrust_min,
    })
}

/// The smallest headroom of the certified `(T, τ)` set (`thrust`'s interval, `certificate`'s
/// torque set) inside the rotors of `mixer`, as a fraction of the rotor range (negative:
/// it does not fit; NaN when the interval itself is refused).
pub fn fit_margin(certificate: &Certificate<f32>, thrust: &ThrustChoice, mixer: &Mixer) -> f32 {
    match thrust_interval(certificate, thrust) {
        Ok((lo, hi)) => mixer.set_margin(lo, hi, &certificate.bounds.torque_set),
        Err(_) => f32::NAN,
    }
}

/// `Ok(margin)` when every condition of `certificate` holds, `thrust`'s interval exists and
/// its certified set leaves at least `required_margin` of every rotor's range free; otherwise the
/// first violated condition, in the paper's order, then the thrust floor, then the rotor fit. A NaN
/// margin fails.
pub fn check(
    certificate: &Certificate<f32>,
    thrust: &ThrustChoice,
    mixer: &Mixer,
    required_margin: f32,
) -> Result<f32, GateFailure> {
    if let Some(c) = certificate.violations().next() {
        return Err(GateFailure {
            condition: c.name,
            lhs: c.lhs,
            rhs: c.rhs,
        });
    }
    let (lo, hi) = thrust_interval(certificate, thrust)?;
    let margin = mixer.set_margin(lo, hi, &certificate.bounds.torque_set);
    if margin >= required_margin {
        Ok(margin)
    } else {
        Err(GateFailure {
            condition: ROTOR_FIT,
            lhs: margin,
            rhs: required_margin,
        })
    }
}
