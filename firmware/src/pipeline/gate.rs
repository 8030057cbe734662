//! The certification gate: a set-up (vehicle, limits, gains, a reference's Assumption 1
//! constants) is flown only if every condition of the a-priori bound certificate holds
//! (Assumption 1, Theorem 1, Lemma 1 and Theorem 2) and the certified `(T, τ)` box
//! `[T_min, T_max] × Π[−τ_i, τ_i]` fits inside the rotors with the configured margin
//! ([`crate::mixer::Mixer::box_margin`]). Pure functions, so the boot report, the arm check and
//! every reference change apply the very same test.

use controller_core::Certificate;

use crate::mixer::Mixer;

/// Name of the box-fit "condition" in refusals and events: `lhs` is the box's smallest
/// headroom, `rhs` the required margin (fractions of the rotor thrust range).
pub const BOX_FIT: &str = "box_fit.margin";

/// The first reason a set-up is not certified: a violated certificate condition with both
/// sides (`lhs > rhs` should hold), or [`BOX_FIT`] with the box's margin and the required one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GateFailure {
    /// Condition name (controller-core's, e.g. `"theorem2.torque_max_yaw"`, or [`BOX_FIT`]).
    pub condition: &'static str,
    /// Left-hand side (for [`BOX_FIT`]: the margin found).
    pub lhs: f32,
    /// Right-hand side (for [`BOX_FIT`]: the margin required).
    pub rhs: f32,
}

/// The smallest headroom of `certificate`'s `(T, τ)` box inside the rotors of `mixer`, as a
/// fraction of the rotor range (negative: it does not fit).
pub fn box_margin(certificate: &Certificate<f32>, mixer: &Mixer) -> f32 {
    let b = &certificate.bounds;
    mixer.box_margin(b.thrust_min, b.thrust_max, &b.torque_max)
}

/// `Ok(margin)` when every condition of `certificate` holds and its box leaves at least
/// `required_margin` of every rotor's range free; otherwise the first violated condition, in
/// the paper's order, then the box fit. A NaN margin fails.
pub fn check(
    certificate: &Certificate<f32>,
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
    let margin = box_margin(certificate, mixer);
    if margin >= required_margin {
        Ok(margin)
    } else {
        Err(GateFailure {
            condition: BOX_FIT,
            lhs: margin,
            rhs: required_margin,
        })
    }
}
