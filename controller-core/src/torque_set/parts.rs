//! The support function of the certified torque set split into its summands: how much of a
//! rotor's (or a rotor pair's) range each part of the law takes.
//!
//! The support function of a Minkowski sum is the sum of its summands' support functions
//! (docs/torque-set.md), so `h(c)` splits exactly into the feedforward's ellipsoid, the
//! gyroscopic box, the feedback's ball, box and disks, and the aligned cylinder. Reading the
//! split along the direction that binds the rotor fit ([`crate::RotorEnvelope::shadow_binding`])
//! says which term of Theorem 2 spends the rotors' authority, and how much a smaller bound on
//! it would free. Source: extension of Theorem 2 (docs/torque-set.md, docs/design.md "Scoring an
//! edited design").

use nalgebra::Vector3;

use super::TorqueSet;
use crate::scalar::Scalar;

/// The summands of [`TorqueSet::support`] along one direction `c` (units of `c` times N m: N
/// when `c` is a rotor's or a rotor pair's row of the mixer, [1/m]). Each part is `≥ 0`, and
/// their sum less the joint bound's saving is `support(c)` up to rounding.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SupportParts<T: Scalar> {
    /// The feedforward's ellipsoid `U_ω̇d |J c|` (Lemma 1's bound on `|ω̇_d|`, turned by any
    /// attitude error).
    pub feedforward: T,
    /// What the ellipsoid would take with `c`'s yaw component dropped, `U_ω̇d |J (c₁, c₂, 0)|`:
    /// `feedforward` minus this is what the desired tilt acceleration landing on the body's yaw
    /// axis costs along `c`.
    pub feedforward_without_yaw: T,
    /// The gyroscopic box `Σ_i |c_i| ½|J_jj − J_kk| U_ωd²`.
    pub gyroscopic: T,
    /// The feedback's ball `r |c|` (the paper's `ι`, or tilt priority's radial MRP term plus
    /// its least trace weight).
    pub feedback_ball: T,
    /// The feedback's box `Σ_i |c_i| b_i` (tilt priority's damping levels `M_ω,i`).
    pub feedback_box: T,
    /// The feedback's disks `Σ_k d_k |c − c_k e_k|` (tilt priority's trace term).
    pub feedback_disks: T,
    /// The aligned feedforward's cylinder, turned or not (the local regime and airmode's
    /// aligned set; zero in Theorem 2's set).
    pub aligned: T,
    /// What the joint bound of the attitude terms frees ([`TorqueSet::joint_saving`], `≥ 0`):
    /// subtracted from the sum of the parts above.
    pub joint_saving: T,
}

impl<T: Scalar> SupportParts<T> {
    /// The sum of the parts: [`TorqueSet::support`] of the same direction, up to rounding.
    pub fn total(&self) -> T {
        self.feedforward
            + self.gyroscopic
            + self.feedback_ball
            + self.feedback_box
            + self.feedback_disks
            + self.aligned
            - self.joint_saving
    }
}

impl<T: Scalar> TorqueSet<T> {
    /// [`TorqueSet::support`] at `c` split into its summands (module documentation). No errors.
    /// Source: the support function of a Minkowski sum (docs/torque-set.md).
    pub fn support_parts(&self, c: &Vector3<T>) -> SupportParts<T> {
        let abs = c.abs();
        let n2 = c.norm_squared();
        let jc = self.inertia.component_mul(c);
        let [a, b] = [self.aligned_acceleration.x, self.aligned_acceleration.y];
        let aligned = if self.aligned_turn > T::zero() {
            self.turned_cylinder_support(&jc)
        } else {
            a * jc.xy().norm() + b * jc.z.abs()
        };
        SupportParts {
            feedforward: self.angular_acceleration * jc.norm(),
            feedforward_without_yaw: self.angular_acceleration * jc.xy().norm(),
            gyroscopic: abs.dot(&self.gyroscopic),
            feedback_ball: self.feedback_radius * n2.sqrt(),
            feedback_box: abs.dot(&self.feedback_box),
            feedback_disks: self.disks_support(c, n2),
            aligned,
            joint_saving: self.joint_saving(c),
        }
    }
}

#[cfg(test)]
mod tests;
