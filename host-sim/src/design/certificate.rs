//! The certificate of a design, from the two functions the firmware trusts:
//! `controller_core::bounds::certify` (Assumption 1, Theorem 1, Lemma 1, Theorem 2, and the
//! torque set of Theorem 2's terms) and `firmware::mixer::Mixer::set_margin` (the certified
//! `(T, τ)` set inside the rotor range).
//!
//! The actuator limits the conditions are evaluated against are what the rotor set delivers:
//! `T_max = Σ_k f_max` and `τ_max,i` = the rotors' capacity on axis `i` alone over the certified
//! thrust interval (the largest `|τ_i|` realisable at both thrust ends with the other torques at
//! zero). The certified set contains `±τ_i e_i` for its per-axis bound `τ_i`, so a set that fits
//! meets Theorem 2's per-axis conditions against these limits. With the tight bounds the
//! certified set takes the least of its own and their norms of `ω_d`, `ω̇_d`
//! ([`super::tight::tightened_set`]), and Theorem 2's conditions are judged with their per-axis
//! bounds against the same limits.

use anyhow::{anyhow, Result};
use controller_core::torque_set::AttitudeJoint;
use controller_core::{
    certify, Certificate, FilterStart, Gains, Limits, TorqueSet, TrajectoryConstants, Vehicle,
};
use firmware::config::RotorConfig;
use firmware::mixer::{BoxFit, Mixer};
use nalgebra::Vector3;

use super::authority::{set_margin, RotorFit, RotorSet};
use super::tight::{tightened_set, TightTorque};
use crate::bounds::certificate::TightCondition;

/// A set-up checked by `certify` and `set_margin`.
#[derive(Clone, Debug)]
pub struct Certified {
    /// The limits derived from the rotor set \[N\], [N m].
    pub limits: Limits<f64>,
    /// `certify` with those limits.
    pub certificate: Certificate<f64>,
    /// `box_fit` of the box of the certified per-axis bounds on the vehicle's rotor range (a
    /// per-axis report; the certified set is inside it).
    pub box_fit: BoxFit,
    /// The certified set fits the vehicle's rotor range.
    pub fits: bool,
    /// The certified set fits the range shrunk by the requested margin at both ends.
    pub fits_with_margin: bool,
    /// Smallest headroom of the certified set over the rotors, fraction of the rotor range.
    pub margin: f64,
    /// The per-axis torque bounds [N m] (body axes) Theorem 2's conditions are judged with:
    /// Theorem 2's, or the tight ones ([`TightTorque::torque_box`]).
    pub torque_box: Vector3<f64>,
    /// The certified torque set [N m] (body axes): Theorem 2's terms
    /// (`Bounds::torque_set`), with the tight norms when certified with the tight bounds.
    pub set: TorqueSet<f64>,
    /// With the tight bounds: Theorem 2's torque conditions judged with both bounds (they
    /// replace the paper's verdict on those three); `None`: the paper's bounds.
    pub tight: Option<Vec<TightCondition>>,
    /// The paper's certified set (Theorem 1's interval × Theorem 2's torque set) fits the range
    /// shrunk by the margin: what the firmware's gate measures (the same as
    /// [`Certified::fits_with_margin`] when certified with the paper's bounds).
    pub paper_fits_with_margin: bool,
    /// How the set was fitted: the whole thrust interval at every torque, or airmode's shadow
    /// and aligned fits (docs/airmode.md).
    pub fit: RotorFit,
    /// With airmode: the smallest headroom of the feedforward at zero attitude error
    /// (`Bounds::aligned_feedforward`) over Theorem 1's interval, as a fraction of the rotor
    /// range (it must exceed the margin); `None` otherwise.
    pub aligned_margin: Option<f64>,
}

impl Certified {
    /// Every condition holds (Theorem 2's torque conditions with the tight bounds when
    /// certified with them) and the certified set fits with the margin.
    pub fn ok(&self) -> bool {
        self.all_hold() && self.fits && self.fits_with_margin
    }

    /// What the firmware's gate re-checks on board (`firmware::pipeline::gate::check`): every
    /// condition with the paper's bounds, and the paper's certified set fits with the margin.
    pub fn paper_certified(&self) -> bool {
        self.certificate.require_feasible().is_ok() && self.paper_fits_with_margin
    }

    /// Every condition holds, Theorem 2's torque conditions judged with the bounds the design
    /// was certified with.
    pub fn all_hold(&self) -> bool {
        match &self.tight {
            None => self.certificate.require_feasible().is_ok(),
            Some(tight) => {
                self.certificate
                    .violations()
                    .all(|v| tight.iter().any(|t| t.name == v.name))
                    && tight.iter().all(|t| t.holds_tight)
            }
        }
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

/// Certifies `gains` for `vehicle` on `rotors` with reference `constants`, with the paper's
/// bounds.
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
    certify_design_with(
        vehicle,
        rotors,
        gains,
        constants,
        margin,
        None,
        RotorFit::Set,
    )
}

/// The f32 copy of a torque set (what the firmware computes from the flight file).
pub fn set_f32(s: &TorqueSet<f64>) -> TorqueSet<f32> {
    TorqueSet {
        inertia: s.inertia.map(|x| x as f32),
        angular_acceleration: s.angular_acceleration as f32,
        gyroscopic: s.gyroscopic.map(|x| x as f32),
        feedback_radius: s.feedback_radius as f32,
        feedback_box: s.feedback_box.map(|x| x as f32),
        feedback_disks: s.feedback_disks.map(|x| x as f32),
        aligned_acceleration: s.aligned_acceleration.map(|x| x as f32),
        aligned_turn: s.aligned_turn as f32,
        // Rounded up by a few ulp: the f32 values stay above the f64 bound they copy.
        attitude_joint: s.attitude_joint.map(|j| AttitudeJoint {
            support_values: j
                .support_values
                .map(|v| v as f32 * (1.0 + 4.0 * f32::EPSILON)),
            turn_over_box: j.turn_over_box.map(|x| x as f32),
        }),
    }
}

/// [`certify_design`] with the tight bounds `tight` ([`super::tight::tight_torque`]; sound, and
/// below Lemma 1's and Theorem 2's): the certified set takes their norms of `ω_d`, `ω̇_d` where
/// they are below its own ([`tightened_set`]; the rotor fit is that set's), and Theorem 2's
/// torque conditions are judged with their per-axis bounds; the paper's verdicts are kept
/// beside ([`Certified::tight`]).
///
/// Errors: as [`certify_design`].
pub fn certify_design_with(
    vehicle: &Vehicle<f64>,
    rotors: &RotorConfig,
    gains: &Gains<f64>,
    constants: &TrajectoryConstants<f64>,
    margin: f64,
    tight: Option<TightTorque>,
    fit: RotorFit,
) -> Result<Certified> {
    let mixer = Mixer::new(rotors).map_err(|e| anyhow!("rotor set refused by the mixer: {e:?}"))?;
    let set = RotorSet::new(rotors).map_err(|e| anyhow!("rotor set: {e}"))?;
    // First pass: the bounds (they do not depend on the limits).
    let probe = Limits {
        thrust_max: set.thrust_total_max(),
        torque_max: Vector3::repeat(1.0),
    };
    let first = certify(vehicle, &probe, gains, constants, FilterStart::Zero)
        .map_err(|e| anyhow!("{}", crate::model::scenario::describe(&e)))?;
    let b = &first.bounds;
    let (t_lo, t_hi) = (b.thrust_min as f32, b.thrust_max as f32);
    let torque_box = tight.map_or(b.torque_max, |t| t.torque_box.inf(&b.torque_max));
    let tau32 = torque_box.map(|x| x as f32);
    let box_fit = mixer.box_fit(t_lo, t_hi, &tau32);
    let paper_set = set_f32(&b.torque_set);
    // The set the design is certified with: the paper's, or with the tight norms.
    let certified_set = tight.map_or(b.torque_set, |t| tightened_set(&b.torque_set, t.rates));
    let certified_set32 = set_f32(&certified_set);
    // The capacity the per-axis conditions are judged against: each axis alone (airmode's at
    // the best thrust for it); the set contains `±τ_i e_i` up to its per-axis extent.
    let capacity = set.axis_capacity(fit, (b.thrust_min, b.thrust_max));
    // A zero capacity is a limit `certify` refuses; keep it positive and let the condition fail.
    let limits = Limits {
        thrust_max: set.thrust_total_max(),
        torque_max: capacity.map(|c| c.max(1e-12)),
    };
    let certificate = certify(vehicle, &limits, gains, constants, FilterStart::Zero)
        .map_err(|e| anyhow!("{}", crate::model::scenario::describe(&e)))?;
    let shrunk = Mixer::new(&shrunk_rotors(rotors, margin))
        .map_err(|e| anyhow!("rotor range shrunk by the margin {margin}: {e:?}"))?;
    let aligned_margin = (fit == RotorFit::Airmode).then(|| {
        let b = &certificate.bounds;
        set.envelope(0.0)
            .set_margin(b.thrust_min, b.thrust_max, &b.aligned_feedforward)
    });
    // What the gate measures in f32 on the range shrunk by the margin: the thrust interval
    // times the set, or with airmode the shadow and the thrust interval alone.
    let fits_shrunk = |s: &TorqueSet<f32>| match fit {
        RotorFit::Set => shrunk.set_margin(t_lo, t_hi, s) >= 0.0,
        RotorFit::Airmode => shrunk.envelope().is_some_and(|e| {
            e.shadow_margin(s) >= 0.0
                && e.set_margin(t_lo, t_hi, &TorqueSet::boxed(Vector3::zeros())) >= 0.0
        }),
    };
    // The local regime's set, as the firmware's gate fits it (`rotor_fit.local`,
    // `rotor_fit.local_shadow`) on the range shrunk by the margin.
    let local_fits_with_margin = certificate
        .local
        .as_ref()
        .is_none_or(|l| fits_shrunk(&set_f32(&l.torque_set)));
    let paper_fits_with_margin = fits_shrunk(&paper_set) && local_fits_with_margin;
    let fits_with_margin = fits_shrunk(&certified_set32) && local_fits_with_margin;
    let fits = match fit {
        RotorFit::Set => mixer.set_margin(t_lo, t_hi, &certified_set32) >= 0.0,
        RotorFit::Airmode => {
            set.envelope(0.0).shadow_margin(&certified_set) >= 0.0
                && set.envelope(0.0).set_margin(
                    b.thrust_min,
                    b.thrust_max,
                    &TorqueSet::boxed(Vector3::zeros()),
                ) >= 0.0
        }
    };
    let tight = tight.map(|_| {
        certificate
            .conditions
            .iter()
            .filter(|c| c.name.starts_with("theorem2.torque_max"))
            .zip(0..3)
            .map(|(c, i)| TightCondition {
                name: c.name.to_owned(),
                lhs: c.lhs,
                rhs_paper: c.rhs,
                rhs_tight: torque_box[i],
                holds_paper: c.holds,
                holds_tight: c.lhs > torque_box[i],
            })
            .collect()
    });
    let thrust = (b.thrust_min, b.thrust_max);
    Ok(Certified {
        limits,
        certificate,
        box_fit,
        fits,
        fits_with_margin,
        margin: match fit {
            RotorFit::Set => set_margin(&set, thrust, &certified_set),
            RotorFit::Airmode => set.envelope(0.0).shadow_margin(&certified_set),
        },
        torque_box,
        set: certified_set,
        tight,
        paper_fits_with_margin,
        fit,
        aligned_margin,
    })
}
