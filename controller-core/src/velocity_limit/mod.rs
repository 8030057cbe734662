//! Velocity-limited position feedback (an extension; docs/velocity-limit.md).
//!
//! The paper's feedback `ubar_p = −σ_p(k_p z₁ + k_v z₂)` is one saturation of a linear
//! combination. Far from the reference it is bang-bang about the line `z₂ = −(k_p/k_v) z₁`, which
//! asks for a deceleration `(k_p/k_v)²|z₁|` the level `M_p` cannot give once
//! `|z₁| > M_p (k_v/k_p)²`: the vehicle crosses the line at high speed and overshoots. On a
//! vehicle whose certificate allows only `M_p ≈ 1 m/s²` (the x500), a fall of a few hundred
//! metres becomes a ±500 m oscillation that takes minutes to die out.
//!
//! This feedback writes the same law as a velocity loop around a position loop with a braking
//! profile, as flight stacks do (ArduPilot's `sqrt_controller`, PX4's velocity limits):
//! `ubar_p = −σ_p(k_v (z₂ + φ(z₁)))` per component, with the desired velocity `−φ(z₁)`
//! - `φ(x) = c x` for `|x| ≤ a/c²` (`c = k_p/k_v`): here `k_v(z₂ + φ) = k_p z₁ + k_v z₂`, the
//!   paper's law, so the local behaviour and every linear analysis are unchanged;
//! - `φ(x) = sign(x) √(2a|x| − a²/c²)` beyond (the speed from which braking at `a` stops at the
//!   reference; continuous with a continuous slope at `a/c²`);
//! - `|φ| ≤ V`, the speed limit.
//!
//! **Bounds.** Every component of `ubar_p` is still in `(−M_p, M_p)`, and Theorem 1, Lemma 1 and
//! Theorem 2 use nothing else about `ubar_p` (the filters bound `u_f`, `u̇`, `ü` from
//! `|ubar_p,i| < M_p` alone), so the certificate is the paper's, unchanged.
//!
//! **Stability of the z-subsystem** (each axis `ż₁ = z₂`, `ż₂ = −σ_p(k_v(z₂ + φ(z₁)))`): the
//! only equilibrium is the origin, where the linearisation is the paper's `s² + k_v s + k_p`;
//! every solution is bounded (`|z₂|` enters `V + ε`, and where `|φ| = V` the sign of `ż₁` points
//! back); the divergence `−k_v σ_p'(·)` is negative everywhere, so by Bendixson's criterion there
//! is no periodic orbit and by Poincaré–Bendixson every solution converges to the origin.
//! What is not claimed: the paper's interconnection with the attitude loop is proved with its
//! own Lyapunov function of the single saturation; for this shape it is tested (campaigns), not
//! re-proved (docs/velocity-limit.md).

use nalgebra::Vector3;

use crate::parameter_error::{positive, ParameterError};
use crate::position_saturation::PositionSaturation;
use crate::scalar::{to_f64, Scalar};

/// The braking profile of the velocity-limited position feedback (extension,
/// docs/velocity-limit.md).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VelocityLimit<T: Scalar> {
    /// Speed limit `V` [m/s] of the desired velocity in the z-coordinates, per inertial axis,
    /// `> 0`.
    pub speed: T,
    /// Braking acceleration `a` [m/s²] of the profile, `0 < a < M_p`: the desired velocity is
    /// one from which braking at `a` stops at the reference.
    pub braking: T,
}

impl<T: Scalar> VelocityLimit<T> {
    /// Checks `V > 0` and `0 < a < M_p` (finite), `M_p` \[m/s²\] being the position saturation
    /// level.
    /// Errors: [`ParameterError::NotPositive`] (`"speed_limit"`, `"braking"`) or
    /// [`ParameterError::OutOfRange`] (`"braking"`, the interval `(0, M_p)`).
    pub fn validate(&self, saturation: T) -> Result<(), ParameterError> {
        positive("speed_limit", self.speed)?;
        positive("braking", self.braking)?;
        if self.braking >= saturation {
            return Err(ParameterError::OutOfRange {
                name: "braking",
                value: to_f64(self.braking),
                low: 0.0,
                high: to_f64(saturation),
            });
        }
        Ok(())
    }

    /// `φ(x)` [m/s] for one component `x = z₁,i` \[m\], with `c = k_p/k_v` \[1/s\]: `c x` inside
    /// `|x| ≤ a/c²`, `sign(x)√(2a|x| − a²/c²)` beyond, clipped to `±V`. Odd and
    /// non-decreasing.
    pub fn profile(&self, x: T, c: T) -> T {
        let a = self.braking;
        let reach = a / (c * c);
        let magnitude = if x.abs() <= reach {
            c * x.abs()
        } else {
            (a * (x.abs() + x.abs()) - a * reach).sqrt()
        };
        let clipped = if magnitude > self.speed {
            self.speed
        } else {
            magnitude
        };
        if x < T::zero() {
            -clipped
        } else {
            clipped
        }
    }

    /// The feedback `ubar_p = −σ_p(k_v (z₂ + φ(z₁)))` [m/s²], inertial, each component in
    /// `(−M_p, M_p)` (its norm, with the norm shape); `z₁` \[m\] and `z₂` [m/s] are the
    /// z-coordinates (eq:Zcoordinates) and `kp` [1/s²], `kv` [1/s], `saturation` (`M_p`, m/s²)
    /// and `shape` the position loop's gains ([`crate::position::PositionGains`]).
    pub fn feedback(
        &self,
        (kp, kv): (T, T),
        (shape, saturation): (PositionSaturation, T),
        z1: &Vector3<T>,
        z2: &Vector3<T>,
    ) -> Vector3<T> {
        let c = kp / kv;
        let desired = z1.map(|x| self.profile(x, c));
        -shape.apply(&((z2 + desired) * kv), saturation)
    }
}

#[cfg(test)]
mod tests;
