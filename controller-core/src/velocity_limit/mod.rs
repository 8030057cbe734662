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
//! With the vertical channel apart (docs/vertical-channel.md) the vertical component is
//! `−σ_z(k_v (z₂,z + φ_z(z₁,z)))` with the channel's two levels, and its profile `φ_z` brakes at
//! `a_up < M_up` above the reference (the descent to it is stopped by an upward acceleration) and
//! at `a_down < M_down` below it ([`VerticalBraking`]).
//!
//! **Bounds.** Every component of `ubar_p` is still a value of the saturation: in `(−M_p, M_p)`,
//! or `(−M_down, M_up)` vertically with the vertical channel. Theorem 1, Lemma 1 and Theorem 2 use
//! nothing else about `ubar_p` (the filters bound `u_f`, `u̇`, `ü` from those levels alone), so
//! the certificate is the one the same gains have without the velocity limit, unchanged.
//!
//! **Stability of the z-subsystem** (each axis `ż₁ = z₂`, `ż₂ = −σ_p(k_v(z₂ + φ(z₁)))`, with
//! `σ_z` and `φ_z` vertically; the argument below uses only that `σ` is strictly increasing
//! through 0 and `φ` non-decreasing with the sign of its argument, so the two sides may differ): the
//! only equilibrium is the origin, where the linearisation is the paper's `s² + k_v s + k_p`;
//! every solution is bounded (`|z₂|` enters `V + ε`, and where `|φ| = V` the sign of `ż₁` points
//! back); the divergence `−k_v σ_p'(·)` is negative everywhere, so by Bendixson's criterion there
//! is no periodic orbit and by Poincaré–Bendixson every solution converges to the origin.
//! What is not claimed: the paper's interconnection with the attitude loop is proved with its
//! own Lyapunov function of the single saturation; for this shape it is tested (campaigns), not
//! re-proved (docs/velocity-limit.md).

use nalgebra::Vector3;

use crate::parameter_error::{positive, ParameterError};
use crate::scalar::{to_f64, Scalar};
use crate::vertical_channel::VerticalChannel;

/// The braking profile of the velocity-limited position feedback (extension,
/// docs/velocity-limit.md).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VelocityLimit<T: Scalar> {
    /// Speed limit `V` [m/s] of the desired velocity in the z-coordinates, per inertial axis,
    /// `> 0`.
    pub speed: T,
    /// Braking acceleration `a` [m/s²] of the profile, `0 < a < M_p`: the desired velocity is
    /// one from which braking at `a` stops at the reference. The vertical axis's too without the
    /// vertical channel apart.
    pub braking: T,
    /// The vertical axis's braking accelerations with the vertical channel apart: required with
    /// it, refused without it.
    pub vertical: Option<VerticalBraking<T>>,
}

/// The vertical profile's braking accelerations with the vertical channel apart
/// (docs/velocity-limit.md, docs/vertical-channel.md), inertial z axis up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VerticalBraking<T: Scalar> {
    /// `a_up` [m/s²], `0 < a_up < M_up`: above the reference, where the descent towards it is
    /// stopped by an upward acceleration.
    pub up: T,
    /// `a_down` [m/s²], `0 < a_down < M_down`: below the reference, where the climb towards it
    /// is stopped by a downward one.
    pub down: T,
}

impl<T: Scalar> VelocityLimit<T> {
    /// This profile with its braking accelerations multiplied by `horizontal` (the horizontal
    /// one, and the vertical one without the vertical channel apart) and by `vertical = (up,
    /// down)` (the vertical channel's two) (dimensionless); the speed limit unchanged. With
    /// factors in `(0, 1]` a profile that [`Self::validate`]s against some levels also validates
    /// against those levels times the same factors. No errors. Source: extension
    /// (docs/envelope-design.md: the local regime's smaller levels).
    pub fn scaled(&self, horizontal: T, vertical: (T, T)) -> Self {
        Self {
            speed: self.speed,
            braking: self.braking * horizontal,
            vertical: self.vertical.map(|b| VerticalBraking {
                up: b.up * vertical.0,
                down: b.down * vertical.1,
            }),
        }
    }

    /// Checks `V > 0` and `0 < a < M_p` (finite), `M_p` \[m/s²\] being the position saturation
    /// level; with the vertical channel apart (`vertical`), `0 < a_up < M_up` and
    /// `0 < a_down < M_down`.
    /// Errors: [`ParameterError::NotPositive`] (`"speed_limit"`, `"braking"`, `"braking_up"`,
    /// `"braking_down"`) or [`ParameterError::OutOfRange`] (`"braking"` outside `(0, M_p)`;
    /// `"braking_up"`, `"braking_down"` outside `(0, M_up)`, `(0, M_down)`, read as 0 when the
    /// vertical channel is on without them, and refused with the interval `(0, 0)` when given
    /// without it).
    pub fn validate(
        &self,
        saturation: T,
        vertical: Option<&VerticalChannel<T>>,
    ) -> Result<(), ParameterError> {
        positive("speed_limit", self.speed)?;
        positive("braking", self.braking)?;
        below("braking", self.braking, saturation)?;
        match (vertical, &self.vertical) {
            (None, None) => Ok(()),
            (Some(channel), Some(b)) => {
                positive("braking_up", b.up)?;
                positive("braking_down", b.down)?;
                below("braking_up", b.up, channel.up)?;
                below("braking_down", b.down, channel.down)
            }
            (Some(channel), None) => Err(ParameterError::OutOfRange {
                name: "braking_up",
                value: 0.0,
                low: 0.0,
                high: to_f64(channel.up),
            }),
            (None, Some(b)) => Err(ParameterError::OutOfRange {
                name: "braking_up",
                value: to_f64(b.up),
                low: 0.0,
                high: 0.0,
            }),
        }
    }

    /// `φ(x)` [m/s] for one component `x = z₁,i` \[m\], with `c = k_p/k_v` \[1/s\]: `c x` inside
    /// `|x| ≤ a/c²`, `sign(x)√(2a|x| − a²/c²)` beyond, clipped to `±V`. Odd and
    /// non-decreasing.
    pub fn profile(&self, x: T, c: T) -> T {
        self.profile_braking_at(x, c, self.braking)
    }

    /// The vertical profile `φ_z(x)` [m/s] for `x = z₁,z` \[m\] (inertial z up), `c` \[1/s\]
    /// as in [`Self::profile`]: with [`VerticalBraking`], braking at `a_up` above the reference
    /// (`x > 0`) and at `a_down` below it; without, [`Self::profile`]. Non-decreasing, with
    /// the sign of `x`, within `±V`, and `c x` near 0 on both sides.
    pub fn vertical_profile(&self, x: T, c: T) -> T {
        match &self.vertical {
            None => self.profile(x, c),
            Some(b) => self.profile_braking_at(x, c, if x > T::zero() { b.up } else { b.down }),
        }
    }

    /// The argument `k_v (z₂ + φ(z₁))` [m/s²] of the position saturation, inertial, for the
    /// z-coordinates `z₁` \[m\], `z₂` [m/s] (eq:Zcoordinates) and the gains `k_p` [1/s²],
    /// `k_v` [1/s]: [`Self::profile`] horizontally, [`Self::vertical_profile`] vertically.
    /// `ubar_p` is the position gains' saturation of it
    /// ([`crate::position::PositionGains::feedback_of`]): each component within the level of its
    /// axis (`M_p`, or `M_up`/`M_down` with the vertical channel apart).
    pub fn argument(&self, (kp, kv): (T, T), z1: &Vector3<T>, z2: &Vector3<T>) -> Vector3<T> {
        let c = kp / kv;
        let desired = Vector3::new(
            self.profile(z1.x, c),
            self.profile(z1.y, c),
            self.vertical_profile(z1.z, c),
        );
        (z2 + desired) * kv
    }

    /// The profile with the braking acceleration `a` [m/s²].
    fn profile_braking_at(&self, x: T, c: T, a: T) -> T {
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
}

/// `value < level`, or [`ParameterError::OutOfRange`] naming `name` with `(0, level)`.
fn below<T: Scalar>(name: &'static str, value: T, level: T) -> Result<(), ParameterError> {
    if value < level {
        Ok(())
    } else {
        Err(ParameterError::OutOfRange {
            name,
            value: to_f64(value),
            low: 0.0,
            high: to_f64(level),
        })
    }
}

#[cfg(test)]
mod tests;
