//! Where a certified set's rotor budget goes: the rotor pair that binds airmode's shadow fit
//! ([`RotorEnvelope::shadow_binding`]) and the newtons each part of the set takes of that pair's
//! range ([`TorqueSet::support_parts`]). `host-sim score` prints it, so an engineer sees which
//! term of Theorem 2 a faster design would have to shrink (docs/design.md, "Scoring an edited
//! design").

use controller_core::{RotorEnvelope, TorqueSet};
use serde::Serialize;

/// The binding pair of a shadow fit and the split of what the set asks of it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FitBinding {
    /// The pair's rotors `(k, l)`, 1-based in the vehicle file's motor order: the set can ask
    /// rotor `l` to push above rotor `k` by more than any other pair's range allows.
    pub rotors: (usize, usize),
    /// What a torque of 1 N m about each body axis (roll, pitch, yaw) asks of the pair [N per
    /// N m]: `d = w_k c_l − w_l c_k`.
    pub newtons_per_newton_metre: [f64; 3],
    /// What the pair can give, `w_k hi − w_l lo` \[N\], on the rotors' whole range.
    pub capacity_n: f64,
    /// `(w_k + w_l)(hi − lo)` \[N\]: the margin's unit; the set fits with a margin `m` iff
    /// `asked_n ≤ capacity_n − m · margin_unit_n`.
    pub margin_unit_n: f64,
    /// What the set asks, `h_S(d)` \[N\]: the sum of `parts`.
    pub asked_n: f64,
    /// The margin left, `(capacity − asked) / ((w_k + w_l)(hi − lo))`, fraction of the rotor
    /// range (the shadow margin; compare with the requested margin).
    pub margin: f64,
    /// The parts of `asked_n` \[N\].
    pub parts: BindingParts,
}

/// The newtons each summand of the certified set takes of the binding pair's range
/// ([`controller_core::torque_set::SupportParts`] along the pair's direction).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BindingParts {
    /// The feedforward's ellipsoid `U_ω̇d |J d|` (Lemma 1) \[N\].
    pub feedforward_n: f64,
    /// Of `feedforward_n`, what its yaw component adds: `U_ω̇d (|J d| − |(J₁₁d₁, J₂₂d₂)|)` \[N\],
    /// the desired tilt acceleration landing on the body's yaw axis under an attitude error.
    pub feedforward_yaw_n: f64,
    /// The gyroscopic box \[N\].
    pub gyroscopic_n: f64,
    /// The feedback's ball (the paper's `ι`; tilt priority's radial MRP term and least trace
    /// weight) \[N\].
    pub feedback_ball_n: f64,
    /// The feedback's box (tilt priority's damping levels) \[N\].
    pub feedback_box_n: f64,
    /// The feedback's disks (tilt priority's trace term) \[N\].
    pub feedback_disks_n: f64,
    /// The aligned feedforward's cylinder (the local regime's set) \[N\].
    pub aligned_n: f64,
    /// What the joint bound of tilt priority's attitude terms frees of the ball, the disks and
    /// the turn-over term's share of the box \[N\], subtracted from the sum of the parts above
    /// ([`TorqueSet::joint_saving`]).
    pub joint_saving_n: f64,
}

/// The binding pair of `set` on `envelope` (the rotors' whole range) and the split of what it
/// asks. No errors. Source: docs/airmode.md (the shadow fit) and docs/torque-set.md (the
/// support function of a Minkowski sum).
pub fn fit_binding(envelope: &RotorEnvelope<f64>, set: &TorqueSet<f64>) -> FitBinding {
    let b = envelope.shadow_binding(set);
    let p = set.support_parts(&b.direction);
    let (k, l) = b.rotors;
    let (lo, hi) = envelope.range;
    FitBinding {
        rotors: (k + 1, l + 1),
        newtons_per_newton_metre: b.direction.into(),
        capacity_n: b.capacity,
        margin_unit_n: (envelope.collective[k] + envelope.collective[l]) * (hi - lo),
        asked_n: p.total(),
        margin: b.margin,
        parts: BindingParts {
            feedforward_n: p.feedforward,
            feedforward_yaw_n: p.feedforward - p.feedforward_without_yaw,
            gyroscopic_n: p.gyroscopic,
            feedback_ball_n: p.feedback_ball,
            feedback_box_n: p.feedback_box,
            feedback_disks_n: p.feedback_disks,
            aligned_n: p.aligned,
            joint_saving_n: p.joint_saving,
        },
    }
}
