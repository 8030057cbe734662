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
//!   step Theorem 2 takes per component);
//! - with tilt priority the radial MRP term is a ball too, the per-axis damping a **box**
//!   (`M_ω,i`), and the trace term `½ vee(G R̃ − R̃ᵀG)` (`G = diag(g)`, `g_min` its least
//!   entry) splits as `G = g_min I + Σ_k (g_k − g_min) e_k e_kᵀ`: the first part is
//!   `g_min vee(½(R̃ − R̃ᵀ))`, of norm `g_min |sin θ| ≤ g_min` (a **ball**), and each rank-one
//!   part is `½(g_k − g_min) (R̃ᵀe_k) × e_k`, orthogonal to `e_k` with norm at most
//!   `½(g_k − g_min)` (a **disk** in the plane orthogonal to body axis `k`). Along axis `i` the
//!   ball and the two other disks add up to `½(g_j + g_k)`, the trace term's per-axis bound.
//!
//! The torque is in the Minkowski sum `S` of these four sets. `S` is convex and symmetric, and
//! its extent along each body axis is Theorem 2's bound `J_ii U_ω̇d + ½|J_jj − J_kk| U_ωd² + ι_i`
//! (each summand attains its extent on the axis), so `S` lies inside the paper's box and
//! touches each of its faces. A linear function `cᵀτ` (a rotor's share of the torque) is at
//! most the support function
//! `h(c) = U_ω̇d |J c| + Σ_i |c_i| (½|J_jj − J_kk| U_ωd² + b_i) + r |c| + Σ_k d_k |c − c_k e_k|` over `S`
//! ([`TorqueSet::support`]); over the box it is `Σ_i |c_i| τ_max,i`, up to `√3` times more.
//! That is what lets the rotor fit ([`TorqueSet`] with the mixer, firmware `Mixer::set_margin`)
//! certify larger feedback levels on the same rotors.
//!
//! With tilt priority the three attitude terms (radial, trace, turn-over) are functions of one
//! attitude error and peak at different attitudes, so the sum of their three sets overcharges
//! them; [`attitude_joint`] bounds them together, and the support takes the smaller of the two
//! bounds direction by direction.
//!
//! Source: extension of Theorem 2 (docs/torque-set.md); each term's set is the one Theorem 2's
//! proof bounds, without the final per-component step.

use nalgebra::{Vector2, Vector3};

use crate::scalar::{lit, Scalar};

pub mod attitude_joint;
mod parts;
pub use attitude_joint::AttitudeJoint;
pub use parts::SupportParts;

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
    /// Half-widths of the feedback's box [N m], body axes: zero for the paper's law, the damping
    /// level `M_ω,i` per axis with tilt priority.
    pub feedback_box: Vector3<T>,
    /// Radii `d_k` [N m] of the feedback's disks, disk `k` in the plane orthogonal to body axis
    /// `k`: zero for the paper's law, tilt priority's trace term `½(g_k − g_min)`.
    pub feedback_disks: Vector3<T>,
    /// `(a, b)` [rad/s²] of the feedforward's inertial part with the body frame on the desired
    /// frame (`R̃ = I`): the cylinder `{J v : |(v₁, v₂)| ≤ a, |v₃| ≤ b}`, which the desired
    /// frame's per-axis bounds of `ω̇_d` give ([`crate::desired_frame_bounds`]); zero in the
    /// certified set of Theorem 2, whose attitude error is any.
    pub aligned_acceleration: Vector2<T>,
    /// `θ` \[rad\], in `[0, π]`: the largest rotation angle of `R̃` the cylinder
    /// `aligned_acceleration` is turned by, the feedforward `J R̃ᵀv` with `v` in the cylinder
    /// (the envelope design's local regime, whose attitude error is bounded:
    /// `crate::bounds::local_torque_set`). Zero: the cylinder itself.
    pub aligned_turn: T,
    /// Tilt priority's attitude terms bounded together ([`AttitudeJoint`]): where its support
    /// along a direction is below what the ball, the disks and the turn-over term's share of
    /// the box charge apart, [`TorqueSet::support`] takes it instead. `None`: the Minkowski
    /// sum alone (the paper's law, and tilt priority with `g₁ ≠ g₂`).
    pub attitude_joint: Option<AttitudeJoint<T>>,
}

impl<T: Scalar> TorqueSet<T> {
    /// The box `|τ_i| ≤ half_widths_i` [N m] (body axes) as a torque set: no ellipsoid, ball or
    /// disk. No errors. Used where only per-axis bounds are known (the thrust alone, the
    /// mixer's box margin).
    pub fn boxed(half_widths: Vector3<T>) -> Self {
        Self {
            inertia: Vector3::zeros(),
            angular_acceleration: T::zero(),
            gyroscopic: Vector3::zeros(),
            feedback_radius: T::zero(),
            feedback_box: half_widths,
            feedback_disks: Vector3::zeros(),
            aligned_acceleration: Vector2::zeros(),
            aligned_turn: T::zero(),
            attitude_joint: None,
        }
    }

    /// The feedforward with the body frame on the desired frame (`R̃ = I`): the cylinder
    /// `{J v : |(v₁, v₂)| ≤ tilt, |v₃| ≤ yaw}` (`tilt`, `yaw` [rad/s²]: bounds on the desired
    /// frame's components of `ω̇_d`) plus the gyroscopic box `gyroscopic` [N m] (bounds on the
    /// components of `(J ω_d) × ω_d`), with no feedback. No errors. Source: extension of Lemma 1
    /// and Theorem 2 ([`crate::desired_frame_bounds`], docs/airmode.md).
    pub fn aligned(inertia: Vector3<T>, tilt: T, yaw: T, gyroscopic: Vector3<T>) -> Self {
        Self {
            inertia,
            angular_acceleration: T::zero(),
            gyroscopic,
            feedback_radius: T::zero(),
            feedback_box: Vector3::zeros(),
            feedback_disks: Vector3::zeros(),
            aligned_acceleration: Vector2::new(tilt, yaw),
            aligned_turn: T::zero(),
            attitude_joint: None,
        }
    }

    /// The set of tilt priority's law (docs/tilt-priority.md): the feedforward's parts as in
    /// [`TorqueSet::new`], and the feedback's ball of radius `radial + g_min` (`radial` [N m] the
    /// MRP term's `(1 + (1 + δ)²) M_ϑ/4`), disks `½(g_k − g_min)` from the trace weights
    /// `trace_weights` (`g` [N m], each `≥ 0`) and the damping box `omega_levels` (`M_ω,i`
    /// [N m]). No errors. Source: extension of Theorem 2 (module documentation).
    pub fn tilt_priority(
        inertia: Vector3<T>,
        angular_velocity: T,
        angular_acceleration: T,
        radial: T,
        trace_weights: Vector3<T>,
        omega_levels: Vector3<T>,
    ) -> Self {
        let g_min = trace_weights.min();
        let half = lit::<T>(0.5);
        let mut s = Self::new(
            inertia,
            angular_velocity,
            angular_acceleration,
            radial + g_min,
            Vector3::zeros(),
        );
        s.feedback_box = omega_levels;
        s.feedback_disks = trace_weights.map(|g| (g - g_min) * half);
        s
    }

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
            feedback_disks: Vector3::zeros(),
            aligned_acceleration: Vector2::zeros(),
            aligned_turn: T::zero(),
            attitude_joint: None,
        }
    }

    /// The support function `h(c) = sup_{τ ∈ S} cᵀτ` for a direction `c` (any length; units of
    /// `c` times N m): `U_ω̇d |J c| + Σ_i |c_i| (gyroscopic_i + feedback_box_i) + r |c|
    /// + Σ_k d_k |c − c_k e_k|` (plus `a |(J₁₁c₁, J₂₂c₂)| + b J₃₃|c₃|` for the aligned cylinder,
    /// or [`TorqueSet::turned_cylinder_support`] of `J c` when it is turned), less
    /// [`TorqueSet::joint_saving`] where the attitude terms' joint bound is the smaller.
    /// `S` is symmetric, so `inf_{τ ∈ S} cᵀτ = −h(c)`. Exact for the
    /// Minkowski sum (the support function of a sum is the sum of the summands' support
    /// functions; a disk's is its radius times the length of `c` projected on its plane); with
    /// the joint bound, an upper bound of the law's torque along `c` that is no longer the
    /// support of one convex set for all `c` at once, which is all the rotor fit reads.
    pub fn support(&self, c: &Vector3<T>) -> T {
        let base = self.support_of_theorem2_parts(c) - self.joint_saving(c);
        let [a, b] = [self.aligned_acceleration.x, self.aligned_acceleration.y];
        if a > T::zero() || b > T::zero() {
            let jc = self.inertia.component_mul(c);
            if self.aligned_turn > T::zero() {
                base + self.turned_cylinder_support(&jc)
            } else {
                base + a * jc.xy().norm() + b * jc.z.abs()
            }
        } else {
            // Not `+ 0`: the sets of Theorem 2 keep their support function bit for bit.
            base
        }
    }

    /// The support function at `y` (`= J c`, [kg m² · units of `c`]) of the union of the
    /// cylinder `{v : |(v₁, v₂)| ≤ a, |v₃| ≤ b}` turned by every rotation of angle at most
    /// `θ = aligned_turn`: `sup cᵀJR̃ᵀv = sup (R̃ y)ᵀv`, and `R̃ y` ranges over the vectors of
    /// length `|y|` within the angle `θ` of `y`. With `β` a vector's angle from the body z axis,
    /// the cylinder's support is `|y| f(β)`, `f(β) = a sin β + b |cos β|`, and a rotation by at
    /// most `θ` moves `β` by at most `θ` (the angle between two directions is a metric on the
    /// sphere). `f` is symmetric about `π/2` and concave on `[0, π/2]` with its maximum
    /// `√(a² + b²)` at `β* = atan2(a, b)`, so the supremum over the reachable `β`, folded into
    /// `[lo, hi] = [max(0, β_y − θ), min(π/2, β_y + θ)]`, is `√(a² + b²)` when `β*` is in it and
    /// `f` at the nearer end otherwise. Exact (every such `β` is reached), and at most the
    /// cylinder plus the ball `2 sin(θ/2) √(a² + b²)` it replaces (`|R̃ᵀv − v| ≤ 2 sin(θ/2)|v|`).
    /// No errors. Source: extension of Theorem 2 (docs/envelope-design.md).
    pub fn turned_cylinder_support(&self, y: &Vector3<T>) -> T {
        let [a, b] = [self.aligned_acceleration.x, self.aligned_acceleration.y];
        let beta = y.xy().norm().atan2(y.z.abs());
        let length = y.norm();
        let lo = (beta - self.aligned_turn).max(T::zero());
        let hi = (beta + self.aligned_turn).min(T::frac_pi_2());
        let peak = a.atan2(b);
        if lo <= peak && peak <= hi {
            length * (a * a + b * b).sqrt()
        } else {
            let at = if peak < lo { lo } else { hi };
            length * (a * at.sin() + b * at.cos())
        }
    }

    /// What [`TorqueSet::attitude_joint`] saves along `c` (`≥ 0`): the attitude terms' charge
    /// apart (the ball `r|c|`, the disks and `|c|ᵀ` the turn-over box) minus their joint
    /// support, where that is smaller; zero without a joint bound.
    pub fn joint_saving(&self, c: &Vector3<T>) -> T {
        let Some(joint) = &self.attitude_joint else {
            return T::zero();
        };
        let n2 = c.norm_squared();
        let apart = self.feedback_radius * n2.sqrt()
            + self.disks_support(c, n2)
            + c.abs().dot(&joint.turn_over_box);
        let together = joint.support(c);
        if together < apart {
            apart - together
        } else {
            T::zero()
        }
    }

    /// The feedback disks' support `Σ_k d_k |c − c_k e_k|` at `c` (`n2 = |c|²`): each disk's
    /// radius times the length of `c` projected on its plane.
    fn disks_support(&self, c: &Vector3<T>, n2: T) -> T {
        (0..3).fold(T::zero(), |acc, k| {
            let d = self.feedback_disks[k];
            if d > T::zero() {
                acc + d * (n2 - c[k] * c[k]).sqrt()
            } else {
                acc
            }
        })
    }

    fn support_of_theorem2_parts(&self, c: &Vector3<T>) -> T {
        let abs = c.abs();
        let n2 = c.norm_squared();
        let disks = self.disks_support(c, n2);
        self.angular_acceleration * self.inertia.component_mul(c).norm()
            + abs.dot(&(self.gyroscopic + self.feedback_box))
            + self.feedback_radius * n2.sqrt()
            + disks
    }

    /// The extent along each body axis `h(e_i)` [N m]: Theorem 2's per-axis bound
    /// `J_ii U_ω̇d + ½|J_jj − J_kk| U_ωd² + ι_i` (plus the aligned cylinder's, turned or not).
    pub fn axis_extents(&self) -> Vector3<T> {
        let d = &self.feedback_disks;
        let a = &self.aligned_acceleration;
        let aligned = if self.aligned_turn > T::zero() {
            Vector3::from_fn(|i, _| {
                let mut e = Vector3::zeros();
                e[i] = self.inertia[i];
                self.turned_cylinder_support(&e)
            })
        } else {
            self.inertia.component_mul(&Vector3::new(a.x, a.x, a.y))
        };
        self.inertia * self.angular_acceleration
            + self.gyroscopic
            + self.feedback_box
            + Vector3::repeat(self.feedback_radius)
            + Vector3::new(d.y + d.z, d.z + d.x, d.x + d.y)
            + aligned
    }
}

#[cfg(test)]
mod tests;
