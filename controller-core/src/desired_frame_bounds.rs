//! Lemma 1 per axis of the desired frame: bounds on the tilt and yaw components of `ω_d` and
//! `ω̇_d` (extension, docs/airmode.md).
//!
//! Lemma 1 bounds the norms `|ω_d|` and `|ω̇_d|`. Theorem 2 needs only the norms, because the
//! feedforward `J R̃ᵀω̇_d` is turned by an attitude error that may be anything. Where the body
//! frame is on the desired frame (`R̃ = I`) the feedforward is `J ω̇_d` itself, and its yaw
//! component is much smaller than the norm: for a constant heading it only comes from the
//! tilt. These bounds certify the feedforward there ([`crate::TorqueSet::aligned`]), which is
//! what airmode's convergence argument needs ([`crate::rotor_envelope`]).
//!
//! With `ν_d = (cos ψ, sin ψ)`, `n = (ν_d, 0)` and `k = n × e₃` (horizontal, across the heading),
//! the paper's `ϖ = (ρ₃ ν_d, −ρᵀν*)` is `ρ × k`, so `|ϖ|² = 1 − s²` with `s = ρᵀk`, and the
//! desired frame is `[υ, ρ × υ, ρ]` with `ρ × υ = (s ρ − k)/|ϖ|`. Then (proven, docs/airmode.md):
//!
//! - `ω_d,3 = (ρ × υ)ᵀυ̇ = (s det(ρ, ρ̇, k) + ψ̇ ρ₃)/|ϖ|²`, so
//!   `|ω_d,3| ≤ (h U_ρ̇ + K_ν̇)/L_ϖ`, with `h = sup|ρ_xy| = √(1 − L_ϖ²)` the largest horizontal
//!   share of the thrust direction (`|s| ≤ |ρ_xy| ≤ h`, `|ϖ| ≥ L_ϖ`);
//! - `(ω_d,1, ω_d,2)` are the components of `ρ̇` across `ρ`: their norm is `|ρ̇| ≤ U_ρ̇`;
//! - `ω̇_d,3` is the derivative of the closed form above: `U_ω̇d,3 = ((U_ρ̇ + h K_ν̇) U_ρ̇ + h U_ρ̈⊥
//!   + K_ν̈)/L_ϖ + 2 h K_ν̇ U_ρ̇/L_ϖ² + 2h (U_ρ̇ + h K_ν̇)(h U_ρ̇ + K_ν̇)/L_ϖ³`;
//! - `(ω̇_d,1, ω̇_d,2) = (ω_d,2 ω_d,3, −ω_d,1 ω_d,3) + (υᵀ[ρ]×ρ̈, υᵀρ̈)`, of norm at most
//!   `U_ω3 U_ρ̇ + U_ρ̈⊥` (`U_ρ̈⊥` the bound on the part of `ρ̈` across `ρ`);
//! - the gyroscopic term `(J ω_d) × ω_d` per axis: `|J₂₂ − J₃₃| U_ρ̇ U_ω3`,
//!   `|J₃₃ − J₁₁| U_ρ̇ U_ω3`, `½|J₁₁ − J₂₂| U_ρ̇²`.
//!
//! Each bound is also capped by Lemma 1's norm bound (a component is at most the norm).

use nalgebra::Vector3;

use crate::scalar::{lit, Scalar};
use crate::torque_set::TorqueSet;

/// Bounds on the desired frame's components of `ω_d` [rad/s] and `ω̇_d` [rad/s²] (extension of
/// Lemma 1, module documentation). Built by `certify` (`Bounds::desired_frame`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DesiredFrameBounds<T: Scalar> {
    /// `h = sup|ρ_xy| = √(1 − L_ϖ²)`: the largest horizontal share of the thrust direction
    /// (dimensionless).
    pub horizontal_share: T,
    /// `U_ρ̇` [rad/s]: bound on `|(ω_d,1, ω_d,2)| = |ρ̇|` (Lemma 1's).
    pub tilt_rate: T,
    /// `U_ω3` [rad/s]: bound on `|ω_d,3|`.
    pub yaw_rate: T,
    /// [rad/s²]: bound on `|(ω̇_d,1, ω̇_d,2)|`.
    pub tilt_acceleration: T,
    /// [rad/s²]: bound on `|ω̇_d,3|`.
    pub yaw_acceleration: T,
    /// [N m]: per-axis bounds on the gyroscopic term `(J ω_d) × ω_d`, body axes.
    pub gyroscopic: Vector3<T>,
}

/// What the desired frame's bounds are computed from: Lemma 1's chain and Assumption 1's
/// heading constants.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChainBounds<T: Scalar> {
    /// `U_ρ̇` [1/s] (Lemma 1).
    pub thrust_direction_rate: T,
    /// Bound on the part of `ρ̈` across `ρ` [1/s²] (`U_ρ̈` of Lemma 1, or its tangential form).
    pub thrust_direction_acceleration_across: T,
    /// `L_ϖ` (dimensionless), Lemma 1's lower bound of `|ϖ|`, in `(0, 1]`.
    pub heading_projection_min: T,
    /// `K_ν̇` [rad/s] (Assumption 1).
    pub heading_rate: T,
    /// `K_ν̈` [rad/s²] (Assumption 1).
    pub heading_acceleration: T,
    /// Lemma 1's `U_ωd` [rad/s], a cap on each component.
    pub angular_velocity: T,
    /// Lemma 1's `U_ω̇d` [rad/s²], a cap on each component.
    pub angular_acceleration: T,
}

impl<T: Scalar> DesiredFrameBounds<T> {
    /// The bounds for Lemma 1's `chain` and the inertia diagonal `inertia` [kg m²] (module
    /// documentation). No errors: `chain` comes from `certify`, whose `L_ϖ` lies in `(0, 1]`.
    /// Source: extension of Lemma 1 (docs/airmode.md).
    pub fn new(chain: &ChainBounds<T>, inertia: &Vector3<T>) -> Self {
        let c = chain;
        let l = c.heading_projection_min;
        let h = (T::one() - l * l).max(T::zero()).sqrt();
        let (r, q) = (
            c.thrust_direction_rate,
            c.thrust_direction_acceleration_across,
        );
        let (kd, kdd) = (c.heading_rate, c.heading_acceleration);
        let two = lit::<T>(2.0);
        let yaw_rate = ((h * r + kd) / l).min(c.angular_velocity);
        let yaw_acceleration = (((r + h * kd) * r + h * q + kdd) / l
            + two * h * kd * r / (l * l)
            + two * h * (r + h * kd) * (h * r + kd) / (l * l * l))
            .min(c.angular_acceleration);
        Self::from_yaw(c, h, (yaw_rate, yaw_acceleration), inertia)
    }

    /// The bounds of the frame built from the compensated heading
    /// ([`crate::heading_compensator`]): its yaw components are bounded by the compensator's
    /// `yaw = (U_ω3 [rad/s], U_ω̇3 [rad/s²])` ([`crate::heading_compensator::yaw_bounds`]), the
    /// tilt components and the gyroscopic term follow from them as in [`Self::new`] (the identities
    /// of the module documentation hold for any heading signal). Nothing is capped by the chain's
    /// `angular_velocity`, `angular_acceleration`: Lemma 1's norms bound the frame built from the
    /// reference heading, not this one. No errors. Source: extension of Lemma 1
    /// ([`crate::heading_compensator`]).
    pub fn compensated(chain: &ChainBounds<T>, yaw: (T, T), inertia: &Vector3<T>) -> Self {
        let l = chain.heading_projection_min;
        let h = (T::one() - l * l).max(T::zero()).sqrt();
        let tilt_rate = chain.thrust_direction_rate;
        // Caps that never bind: the norm of the components themselves.
        let uncapped = ChainBounds {
            angular_velocity: (tilt_rate * tilt_rate + yaw.0 * yaw.0).sqrt(),
            angular_acceleration: yaw.0 * tilt_rate + chain.thrust_direction_acceleration_across,
            ..*chain
        };
        Self::from_yaw(&uncapped, h, yaw, inertia)
    }

    /// The tilt components and the gyroscopic term for the yaw bounds `yaw`, capped by the chain's
    /// norms (module documentation).
    fn from_yaw(c: &ChainBounds<T>, h: T, yaw: (T, T), inertia: &Vector3<T>) -> Self {
        let (yaw_rate, yaw_acceleration) = yaw;
        let (r, q) = (
            c.thrust_direction_rate,
            c.thrust_direction_acceleration_across,
        );
        let tilt_rate = r.min(c.angular_velocity);
        let tilt_acceleration = (yaw_rate * tilt_rate + q).min(c.angular_acceleration);
        let j = inertia;
        let half = lit::<T>(0.5);
        let w2 = c.angular_velocity * c.angular_velocity;
        let gyroscopic = Vector3::new(
            (j.y - j.z).abs() * (tilt_rate * yaw_rate).min(half * w2),
            (j.z - j.x).abs() * (tilt_rate * yaw_rate).min(half * w2),
            half * (j.x - j.y).abs() * tilt_rate * tilt_rate,
        );
        Self {
            horizontal_share: h,
            tilt_rate,
            yaw_rate,
            tilt_acceleration,
            yaw_acceleration,
            gyroscopic,
        }
    }

    /// Bounds on the norms `|ω_d|` [rad/s] and `|ω̇_d|` [rad/s²] from the components: the
    /// desired frame is orthonormal, so `|ω_d| ≤ √(U_ρ̇² + U_ω3²)` and likewise for `ω̇_d`; each
    /// capped by Lemma 1's norm bound `lemma1 = (U_ωd, U_ω̇d)`, so never above it. Theorem 2's
    /// feedforward `J R̃ᵀω̇_d` turned by any `R̃` has at most these norms: the certified torque
    /// set ([`TorqueSet`], `Bounds::torque_set`) takes them. No errors.
    /// Source: extension of Lemma 1 (module documentation; docs/torque-set.md).
    pub fn norm_bounds(&self, lemma1: (T, T)) -> (T, T) {
        let hypot = |a: T, b: T| (a * a + b * b).sqrt();
        (
            hypot(self.tilt_rate, self.yaw_rate).min(lemma1.0),
            hypot(self.tilt_acceleration, self.yaw_acceleration).min(lemma1.1),
        )
    }

    /// The feedforward's set with the body frame on the desired frame (`R̃ = I`, no feedback):
    /// [`TorqueSet::aligned`] with these bounds, for the inertia diagonal `inertia` [kg m²].
    pub fn aligned_feedforward(&self, inertia: &Vector3<T>) -> TorqueSet<T> {
        TorqueSet::aligned(
            *inertia,
            self.tilt_acceleration,
            self.yaw_acceleration,
            self.gyroscopic,
        )
    }
}

#[cfg(test)]
pub(crate) mod tests;
