//! The certification gate: a set-up (vehicle, limits, gains, a reference's Assumption 1
//! constants) is flown only if every condition of the a-priori bound certificate holds
//! (Assumption 1, Theorem 1, Lemma 1 and Theorem 2, then the extensions' conditions) and the
//! rotors realise the certified `(T, τ)` with the configured margin. `[T_lo, T_hi]` is the
//! configured thrust's interval (Theorem 1's `[T_min, T_max]` for the paper's `T = m|u|`,
//! `[T_floor, T_max]` for the no-dive thrust; [`ThrustChoice::interval`]) and `S` the torque
//! set of Theorem 2's terms ([`controller_core::TorqueSet`]: inside the box `Π[−τ_i, τ_i]` of its
//! per-axis bounds, so every box that fitted still fits). The rotor fits, in this order:
//!
//! - without airmode: the set `[T_lo, T_hi] × S` ([`ROTOR_FIT`],
//!   [`crate::mixer::Mixer::set_margin`]); with the envelope design's local regime, also its
//!   torque set over the same interval ([`ROTOR_FIT_LOCAL`]);
//! - with airmode ([`FlightConfig::airmode`], docs/airmode.md): Theorem 1's interval
//!   `[T_min, T_max]` alone, at zero torque ([`ROTOR_FIT_THRUST`]; not the no-dive thrust's
//!   floor, which airmode lifts into the thrusts the rotors realise anyway: at zero torque that
//!   is at least the shrunk range's collective minimum); the shadow of `S`, every torque of `S` at *some* thrust
//!   ([`ROTOR_FIT_SHADOW`], [`crate::mixer::Mixer::shadow_margin`]); with a local regime, the
//!   shadow of its torque set ([`ROTOR_FIT_LOCAL_SHADOW`]). Airmode then moves the thrust to
//!   where the rotors realise the law's torque, so the mixer gives nothing up.
//!
//! Every margin is a fraction of the rotor range on the rotors' own range, compared with the
//! required one: shrinking the range by `m` at both ends lowers each of these margins by `m`
//! exactly, so "margin ≥ m" is "fits the range airmode flies" (the range shrunk by `m`,
//! [`airmode_envelope`]). Pure functions, so the boot report, the arm check and every reference
//! change apply the very same test.

pub use crate::gate_failure::GateFailure;
use controller_core::{Certificate, RotorEnvelope, TorqueSet};
use nalgebra::Vector3;

use crate::config::{FlightConfig, ThrustChoice};
use crate::mixer::Mixer;

/// Name of the rotor fit of the certified set `[T_lo, T_hi] × S` in refusals and events: `lhs`
/// is its smallest headroom, `rhs` the required margin (fractions of the rotor thrust range).
pub const ROTOR_FIT: &str = "rotor_fit.margin";

/// Name of the rotor fit of the local regime's torque set over `[T_lo, T_hi]` (no airmode):
/// `lhs` its smallest headroom, `rhs` the required margin (fractions of the rotor range).
pub const ROTOR_FIT_LOCAL: &str = "rotor_fit.local";

/// Name of airmode's thrust fit, Theorem 1's `[T_min, T_max]` at zero torque: `lhs` its smallest headroom,
/// `rhs` the required margin (fractions of the rotor range).
pub const ROTOR_FIT_THRUST: &str = "rotor_fit.thrust";

/// Name of airmode's shadow fit of the certified torque set (every torque at some thrust): `lhs`
/// the shadow margin ([`crate::mixer::Mixer::shadow_margin`]), `rhs` the required margin
/// (fractions of the rotor range).
pub const ROTOR_FIT_SHADOW: &str = "rotor_fit.shadow";

/// Name of airmode's shadow fit of the local regime's torque set: `lhs` its shadow margin, `rhs`
/// the required margin (fractions of the rotor range).
pub const ROTOR_FIT_LOCAL_SHADOW: &str = "rotor_fit.local_shadow";

/// Name of the thrust-floor "condition": `lhs` is the floor, `rhs` Theorem 1's `T_min` \[N\]
/// (a floor above it would raise the thrust above the paper's).
pub const THRUST_FLOOR: &str = "thrust_floor";

/// One rotor fit the gate checks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RotorFit {
    /// Its name in refusals and events ([`ROTOR_FIT`], [`ROTOR_FIT_SHADOW`], …).
    pub name: &'static str,
    /// What is fitted, for the boot banner (ASCII).
    pub what: &'static str,
    /// Its headroom, a fraction of the rotor range \[dimensionless\] (negative: it does not
    /// fit; `−∞` when a rotor cannot carry collective).
    pub margin: f32,
}

/// The rotor fits of a set-up, in the gate's order (one to three; module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RotorFits {
    fits: [RotorFit; 3],
    len: usize,
}

impl RotorFits {
    fn one(name: &'static str, what: &'static str, margin: f32) -> Self {
        let fit = RotorFit { name, what, margin };
        Self {
            fits: [fit; 3],
            len: 1,
        }
    }

    fn push(&mut self, name: &'static str, what: &'static str, margin: f32) {
        // At most three fits are ever pushed (module documentation).
        if let Some(slot) = self.fits.get_mut(self.len) {
            *slot = RotorFit { name, what, margin };
            self.len += 1;
        }
    }

    /// The fits, in the gate's order.
    pub fn as_slice(&self) -> &[RotorFit] {
        &self.fits[..self.len]
    }

    /// The smallest margin of the fits (a fraction of the rotor range; NaN if any is NaN): what
    /// the gate returns when every fit holds.
    pub fn smallest(&self) -> f32 {
        let mut smallest = f32::INFINITY;
        for f in self.as_slice() {
            if f.margin.is_nan() {
                return f32::NAN;
            }
            if f.margin < smallest {
                smallest = f.margin;
            }
        }
        smallest
    }

    /// The margin of the fit named `name`, if the gate checks it.
    pub fn margin_of(&self, name: &str) -> Option<f32> {
        self.as_slice()
            .iter()
            .find(|f| f.name == name)
            .map(|f| f.margin)
    }
}

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

/// The rotor fits of `certificate` for the set-up `cfg` (its thrust and airmode) on the rotors
/// of `mixer`, in the gate's order (module documentation), or the failure [`THRUST_FLOOR`].
pub fn rotor_fits(
    certificate: &Certificate<f32>,
    cfg: &FlightConfig,
    mixer: &Mixer,
) -> Result<RotorFits, GateFailure> {
    let (lo, hi) = thrust_interval(certificate, &cfg.thrust)?;
    let set = &certificate.bounds.torque_set;
    let local = certificate.local.as_ref().map(|l| &l.torque_set);
    Ok(if cfg.airmode {
        let thrust_alone = TorqueSet::boxed(Vector3::zeros());
        let b = &certificate.bounds;
        let mut fits = RotorFits::one(
            ROTOR_FIT_THRUST,
            "Theorem 1's thrust interval at zero torque",
            mixer.set_margin(b.thrust_min, b.thrust_max, &thrust_alone),
        );
        fits.push(
            ROTOR_FIT_SHADOW,
            "certified set's shadow (each torque at some thrust)",
            mixer.shadow_margin(set),
        );
        if let Some(l) = local {
            fits.push(
                ROTOR_FIT_LOCAL_SHADOW,
                "local regime set's shadow",
                mixer.shadow_margin(l),
            );
        }
        fits
    } else {
        let mut fits = RotorFits::one(ROTOR_FIT, "certified set", mixer.set_margin(lo, hi, set));
        if let Some(l) = local {
            fits.push(
                ROTOR_FIT_LOCAL,
                "local regime's set",
                mixer.set_margin(lo, hi, l),
            );
        }
        fits
    })
}

/// The smallest headroom of the rotor fits of `certificate` for `cfg` on the rotors of `mixer`
/// ([`rotor_fits`]), as a fraction of the rotor range (negative: one does not fit; NaN when the
/// thrust interval itself is refused). Without airmode or a local regime: the certified set's
/// margin, [`crate::mixer::Mixer::set_margin`].
pub fn fit_margin(certificate: &Certificate<f32>, cfg: &FlightConfig, mixer: &Mixer) -> f32 {
    rotor_fits(certificate, cfg, mixer).map_or(f32::NAN, |f| f.smallest())
}

/// `Ok(margin)` when every condition of `certificate` holds, `cfg`'s thrust interval exists and
/// every rotor fit ([`rotor_fits`]) leaves at least `cfg.box_margin` of every rotor's range free
/// (`margin` the smallest of them); otherwise the first failure: the certificate's conditions in
/// the paper's order (the extensions' after), then the thrust floor, then the fits in their
/// order. A NaN margin fails.
pub fn check(
    certificate: &Certificate<f32>,
    cfg: &FlightConfig,
    mixer: &Mixer,
) -> Result<f32, GateFailure> {
    if let Some(c) = certificate.violations().next() {
        return Err(GateFailure {
            condition: c.name,
            lhs: c.lhs,
            rhs: c.rhs,
        });
    }
    let fits = rotor_fits(certificate, cfg, mixer)?;
    let required = cfg.box_margin;
    // `margin >= required`, false when either is NaN.
    let leaves = |margin: f32| margin.partial_cmp(&required).is_some_and(|o| o.is_ge());
    match fits.as_slice().iter().find(|f| !leaves(f.margin)) {
        None => Ok(fits.smallest()),
        Some(f) => Err(GateFailure {
            condition: f.name,
            lhs: f.margin,
            rhs: required,
        }),
    }
}

/// The rotor envelope airmode flies for `cfg` on the rotors of `mixer`: the rotors' range shrunk
/// by [`FlightConfig::box_margin`] below its top and by [`FlightConfig::airmode_low_margin`]
/// (at most `box_margin`) above its bottom, so it contains the range where the gate's shadow
/// fits were checked; or `None` when airmode is off (or a rotor cannot carry collective, which
/// the gate refuses).
pub fn airmode_envelope(cfg: &FlightConfig, mixer: &Mixer) -> Option<RotorEnvelope<f32>> {
    if cfg.airmode {
        // `min`/`max`, not `clamp`: no panic whatever the configured margins are.
        let low = cfg.airmode_low_margin.max(0.0).min(cfg.box_margin);
        mixer.envelope().map(|e| e.shrunk_ends(low, cfg.box_margin))
    } else {
        None
    }
}

/// With airmode, the smallest headroom the feedforward at zero attitude error
/// (`Bounds::aligned_feedforward`, and the local regime's when there is one) leaves over Theorem
/// 1's `[T_min, T_max]` on the rotors of `mixer`, a fraction of the rotor range; `None` without
/// airmode. At least the required margin: airmode's convergence argument is a proof; below it,
/// convergence is shown by simulation only (docs/airmode.md). Information only: the gate does
/// not require it.
pub fn aligned_margin(
    certificate: &Certificate<f32>,
    cfg: &FlightConfig,
    mixer: &Mixer,
) -> Option<f32> {
    if !cfg.airmode {
        return None;
    }
    let b = &certificate.bounds;
    let global = mixer.set_margin(b.thrust_min, b.thrust_max, &b.aligned_feedforward);
    Some(match &certificate.local {
        None => global,
        // The local regime is where the attitude error ends up: its feedforward must fit too.
        Some(l) => {
            global.min(mixer.set_margin(b.thrust_min, b.thrust_max, &l.bounds.aligned_feedforward))
        }
    })
}
