//! The certified torque set: the set Theorem 2's argument confines the commanded torque to,
//! kept with its shape instead of the box of its per-axis extents.
//!
//! Theorem 2 bounds each torque component by the sum of three per-axis worst cases. The three
//! terms do not reach their worst cases along the same directions, so the torque lies in a
//! smaller set than the box of those sums: with `w = R̃ᵀω_d` (`|w| ≤ U_ωd`),
//! `v = R̃ᵀω̇_d` (`|v| ≤ U_ω̇d`, a rotation keeps the norm) and `|ϑ̃| ≤ 1 + δ`,
//!
//! - the feedforward's inertial part `−J v` lies in the **ellipsoid** `{J v : |v| ≤ U_ω̇d}`;
//! - its gyroscopic part `(J w) × w`, component `i` = `(J_jj − J_kk) w_j w_k`, lies in the
//!   **box** `½|J_jj − J_kk| U_ωd²` (as in Theorem 2, since `|w_j w_k| ≤ ½|w|²`);
//! - the paper's feedback `(1 + |ϑ̃|²)/4 s_ϑ + s_ω` has radial saturations, so it lies in the
//!   **ball** of radius `ι = (1 + (1 + δ)²) M_ϑ/4 + M_ω` (the triangle inequality on norms, the
//!   step Theorem 2 takes per component). With tilt priority only the radial MRP term is a ball;
//!   the trace term and the per-axis damping are a **box** (`ι_i` minus the ball's radius).
//!
//! The torque is in the Minkowski sum `S` of these four sets. `S` is convex and symmetric, and
//! its extent along each body axis is Theorem 2's bound `J_ii U_ω̇d + ½|J_jj − J_kk| U_ωd² + ι_i`
//! (each summand attains its extent on the axis), so `S` lies inside the paper's box and
//! touches each of its faces. A linear function `cᵀτ` (a rotor's share of the torque) is at
//! most the support function
//! `h(c) = U_ω̇d |J c| + Σ_i |c_i| (½|J_jj − J_kk| U_ωd² + b_i) + r |c|` over `S`
//! ([`TorqueSet::support`]); over the box it is `Σ_i |c_i| τ_max,i`, up to `√3` times more.
//! That is what lets the rotor fit ([`TorqueSet`] with the mixer, firmware `Mixer::set_margin`)
//! certify larger feedback levels on the same rotors.
//!
//! Source: extension of Theorem 2 (docs/torque-set.md); each term's set is the one Theorem 2's
//! proof bounds, without the final per-component step.

use nalgebra::Vector3;

use crate::scalar::{lit, Scalar};

/// The certified torque set `S` [N m], body frame: the Minkowski sum of the feedforward's
/// ellipsoid, the gyroscopic box, the feedback's ball and the feedback's box (module
/// documentation). Built by `certify` (`Bounds::torque_set`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TorqueSet<T: Scalar> {
    /// Inertia diagonal `(J₁₁, J₂₂, J₃₃)` [kg m²], body axes.
    pub inertia: Vector3<T>,
    /// `U_ω̇d` [rad/s²]: the ellipsoid is `{J v : |v| ≤ U_ω̇d}` (Lemma 1, or its extension).
    pub angular_acceleration: T,
    /// Half-widths of the gyroscopic box `½|J_jj − J_kk| U_ωd²` [N m], body axes.
    pub gyroscopic: Vector3<T>,
    /// Radius of the feedback's ball [N m]: `ι` for the paper's law, the radial MRP term's
    /// `(1 + (1 + δ)²) M_ϑ/4` with tilt priority.
    pub feedback_radius: T,
    /// Half-widths of the feedback's box [N m], body axes: zero for the paper's law, the trace
    /// term plus the damping level per axis with tilt priority.
    pub feedback_box: Vector3<T>,
}

impl<T: Scalar> TorqueSet<T> {
    /// The set of a set-up from its inertia diagonal `inertia` [kg m²], the bounds `U_ωd`
    /// (`angular_velocity` [rad/s]) and `U_ω̇d` (`angular_acceleration` [rad/s²]), the radius of
    /// the feedback's radial part `feedback_radius` [N m] and the per-axis feedback levels
    /// `feedback_axes` (`ι_i` [N m], body axes, each at least the radius). No errors: a level
    /// below the radius is taken as the radius (the box part is then zero).
    /// Source: Theorem 2's terms (module documentation).
    pub fn new(
        inertia: Vector3<T>,
        angular_velocity: T,
        angular_acceleration: T,
        feedback_radius: T,
        feedback_axes: Vector3<T>,
    ) -> Self {
        let w2 = angular_velocity * angular_velocity;
        let half = lit::<T>(0.5);
        Self {
            inertia,
            angular_acceleration,
            gyroscopic: Vector3::from_fn(|i, _| {
                let (j, k) = ((i + 1) % 3, (i + 2) % 3);
                half * (inertia[j] - inertia[k]).abs() * w2
            }),
            feedback_radius,
            feedback_box: feedback_axes.map(|l| {
                let excess = l - feedback_radius;
                if excess > T::zero() {
                    excess
                } else {
                    T::zero()
                }
            }),
        }
    }

    /// The support function `h(c) = sup_{τ ∈ S} cᵀτ` for a direction `c` (any length; units of
    /// `c` times N m): `U_ω̇d |J c| + Σ_i |c_i| (gyroscopic_i + feedback_box_i) + r |c|`.
    /// `S` is symmetric, so `inf_{τ ∈ S} cᵀτ = −h(c)`. Exact for the Minkowski sum (the support
    /// function of a sum is the sum of the summands' support functions).
    pub fn support(&self, c: &Vector3<T>) -> T {
        let abs = c.abs();
        self.angular_acceleration * self.inertia.component_mul(c).norm()
            + abs.dot(&(self.gyroscopic + self.feedback_box))
            + self.feedback_radius * c.norm()
    }

    /// The extent along each body axis `h(e_i)` [N m]: Theorem 2's per-axis bound
    /// `J_ii U_ω̇d + ½|J_jj − J_kk| U_ωd² + ι_i`.
    pub fn axis_extents(&self) -> Vector3<T> {
        self.inertia * self.angular_acceleration
            + self.gyroscopic
            + self.feedback_box
            + Vector3::repeat(self.feedback_radius)
    }
}

#[cfg(test)]
mod tests;
