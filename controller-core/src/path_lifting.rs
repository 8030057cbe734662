//! The hybrid dynamic path-lifting mechanism `𝓗_l` of the Appendix.
//!
//! It lifts the attitude error `R̃ = R_dᵀR` from SO(3) to an MRP `ϑ̃` in the ball
//! `(1 + δ)𝔹³`, continuously between jumps and without chattering at 180°:
//! - a memory quaternion `q̂` picks the sign of the quaternion of `R̃` through
//!   `Φ(q̂, R̃) = argmax_{p ∈ 𝒬(R̃)} q̂ᵀp` (Mayhew, Sanfelice and Teel 2013), so the lifted
//!   quaternion moves continuously; `q̂` is reset to `Φ` when `dist(q̂, 𝒬(R̃)) = 1 − q̂ᵀΦ ≥ α`;
//! - a sign `m* ∈ {−1, +1}` chooses between the principal MRP and the shadow MRP; it flips when
//!   `|φ(m*Φ)| ≥ 1 + δ`, the hysteresis margin `δ` that keeps noise from toggling it.
//!
//! Sampled reading (documented choice): the jump rules are evaluated once per control sample,
//! before the torque is computed, and repeated until the state is in the flow set
//! `C_l = C_q ∩ C_m`; when both jump conditions hold, both jumps are applied (the `q̂` reset
//! first, then the `m*` flip, which the reset leaves still required). The initial memory is the
//! quaternion of `R̃(0)` with `q₀ ≥ 0` and `m* = +1`.

use nalgebra::{Matrix3, Quaternion, Vector3};

use crate::mrp::{mrp_from_quaternion, quaternion_from_rotation};
use crate::scalar::{norm, Scalar};

/// Counters of the jumps of the path-lifting mechanism since construction.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct JumpCounters {
    /// Resets of the memory quaternion `q̂ ← Φ(q̂, R̃)` (jumps from `D_q`).
    pub q_hat_resets: u32,
    /// Flips of the MRP sign `m* ← −m*` (jumps from `D_m`: principal ↔ shadow MRP).
    pub m_flips: u32,
}

/// State `x_l = (q̂, m*)` of the path-lifting mechanism (the `R̃` part is the measurement).
#[derive(Clone, Copy, Debug)]
pub struct PathLifting<T: Scalar> {
    memory: Option<Quaternion<T>>,
    sign: T,
    hysteresis: T,
    reset_threshold: T,
    counters: JumpCounters,
}

/// The lifted attitude error produced at one sample.
#[derive(Clone, Copy, Debug)]
pub struct LiftedError<T: Scalar> {
    /// MRP attitude error `ϑ̃` (dimensionless), `|ϑ̃| ≤ 1 + δ`, with `R(ϑ̃) = R̃`.
    pub mrp: Vector3<T>,
    /// Lifted quaternion `m* Φ(q̂, R̃)` (unit, dimensionless).
    pub quaternion: Quaternion<T>,
    /// Jumps applied at this sample.
    pub jumps: JumpCounters,
}

/// Largest number of jumps in one sample: a reset then a flip. More would mean a bug.
const MAX_JUMPS_PER_SAMPLE: u32 = 4;

impl<T: Scalar> PathLifting<T> {
    /// A path lifting with hysteresis `δ > 0` and memory reset threshold `α ∈ (0, 1)`.
    ///
    /// The parameters are validated by [`crate::Controller::new`]; here they are taken as given.
    /// The memory is initialised at the first call of [`PathLifting::lift`].
    /// Source: Appendix, `𝓗_l`, parameters `δ` and `α`.
    pub fn new(hysteresis: T, reset_threshold: T) -> Self {
        Self {
            memory: None,
            sign: T::one(),
            hysteresis,
            reset_threshold,
            counters: JumpCounters::default(),
        }
    }

    /// Jumps counted since construction.
    pub fn counters(&self) -> JumpCounters {
        self.counters
    }

    /// The memory quaternion `q̂`, once initialised.
    pub fn memory(&self) -> Option<Quaternion<T>> {
        self.memory
    }

    /// The MRP sign `m*` (+1 principal, −1 shadow), as ±1.
    pub fn sign(&self) -> T {
        self.sign
    }

    /// Lifts the attitude error `R̃ = R_dᵀR` (3×3 rotation, body frame to desired frame) to the
    /// MRP `ϑ̃ = φ(m* Φ(q̂, R̃))`, applying the jumps the sample requires first.
    ///
    /// Output: [`LiftedError`] with `|ϑ̃| ≤ 1 + δ` and `R(ϑ̃) = R̃`. Never fails for a rotation
    /// matrix; a non-finite `R̃` must be rejected by the caller (the controller does).
    /// Source: Appendix (`C_q`, `D_q`, `C_m`, `D_m`, `G_l`, output `ϑ̃`).
    pub fn lift(&mut self, error_rotation: &Matrix3<T>) -> LiftedError<T> {
        let mut q = quaternion_from_rotation(error_rotation);
        let memory = match self.memory {
            Some(m) => m,
            None => {
                if q.w < T::zero() {
                    q = -q;
                }
                self.memory = Some(q);
                q
            }
        };
        let mut memory = memory;
        let mut jumps = JumpCounters::default();
        let limit = T::one() + self.hysteresis;
        let (mrp, lifted) = loop {
            // Φ(q̂, R̃): the member of 𝒬(R̃) = {q, −q} closest to the memory.
            let phi = if memory.dot(&q) >= T::zero() { q } else { -q };
            let dist = T::one() - memory.dot(&phi);
            let lifted = phi * self.sign;
            // φ is finite here: |φ(m*Φ)| → ∞ only when m*Φ → (−1, 0), which D_m catches first.
            let mrp = mrp_from_quaternion(&lifted);
            let in_dm = match mrp {
                Some(m) => norm(&m) > limit,
                None => true,
            };
            let in_dq = dist > self.reset_threshold;
            if !(in_dq || in_dm) || jumps.q_hat_resets + jumps.m_flips >= MAX_JUMPS_PER_SAMPLE {
                break (mrp.unwrap_or_else(Vector3::zeros), lifted);
            }
            if in_dq {
                memory = phi;
                jumps.q_hat_resets += 1;
            } else {
                self.sign = -self.sign;
                jumps.m_flips += 1;
            }
        };
        self.memory = Some(memory);
        self.counters.q_hat_resets += jumps.q_hat_resets;
        self.counters.m_flips += jumps.m_flips;
        LiftedError {
            mrp,
            quaternion: lifted,
            jumps,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mrp::{rotation_from_mrp, rotation_from_quaternion};
    use approx::assert_relative_eq;
    use nalgebra::{Rotation3, Unit, UnitQuaternion};
    use proptest::prelude::*;

    fn axis() -> impl Strategy<Value = Vector3<f64>> {
        (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64)
            .prop_filter("nonzero", |(a, b, c)| a * a + b * b + c * c > 1e-2)
            .prop_map(|(a, b, c)| Vector3::new(a, b, c).normalize())
    }

    fn rot(axis: Vector3<f64>, angle: f64) -> Matrix3<f64> {
        Rotation3::from_axis_angle(&Unit::new_normalize(axis), angle).into_inner()
    }

    proptest! {
        /// Along a continuous rotation path through and past 180°, the lifted MRP stays in the
        /// ball (1 + δ)𝔹³, represents R̃, and moves continuously except at counted jumps.
        #[test]
        fn lifted_mrp_bounded_represents_and_continuous(a in axis(), b in axis(),
            rate in 0.5..8.0f64) {
            let delta = 0.02;
            let mut lifting = PathLifting::new(delta, 0.25);
            let dt = 0.01;
            let mut prev: Option<Vector3<f64>> = None;
            for k in 0..800 {
                let t = k as f64 * dt;
                // Wander over SO(3): a spin about `a` composed with a slower spin about `b`.
                let r = rot(a, rate * t) * rot(b, 0.7 * rate * t);
                let out = lifting.lift(&r);
                prop_assert!(out.mrp.norm() <= 1.0 + delta + 1e-12);
                assert_relative_eq!(rotation_from_mrp(&out.mrp), r, epsilon = 1e-9);
                if let Some(p) = prev {
                    if out.jumps.m_flips == 0 {
                        // Flow: |Δϑ| ≤ max|T(ϑ)| |ω| dt with |T| ≤ (1 + (1+δ)²)/4 and |ω| ≤ 1.7 rate.
                        let bound = 0.6 * 1.7 * rate * dt + 1e-9;
                        prop_assert!((out.mrp - p).norm() <= bound,
                            "jump in ϑ without a flip: {} > {}", (out.mrp - p).norm(), bound);
                    }
                }
                prev = Some(out.mrp);
            }
        }
    }

    #[test]
    fn initial_memory_takes_nonnegative_scalar_and_principal_mrp() {
        let r = rot(Vector3::x(), 3.0);
        let mut l = PathLifting::new(0.02, 0.25);
        let out = l.lift(&r);
        assert!(l.memory().unwrap().w >= 0.0);
        assert_eq!(l.sign(), 1.0);
        assert!(out.mrp.norm() <= 1.0);
        assert_eq!(l.counters(), JumpCounters::default());
    }

    /// Noise around exactly 180°: the hysteresis keeps the MRP sign from chattering, where the
    /// memoryless `q₀ ≥ 0` choice would switch at every sign change of the noise.
    #[test]
    fn hysteresis_prevents_chattering_at_180_degrees() {
        let mut l = PathLifting::new(0.02, 0.25);
        let mut memoryless_switches = 0;
        let mut last_sign = None;
        // Deterministic pseudo-noise of ±0.5° about π, crossing π back and forth.
        for k in 0..1000 {
            let noise = 0.5f64.to_radians() * ((k as f64) * 1.7).sin();
            let r = rot(Vector3::z(), core::f64::consts::PI + noise);
            l.lift(&r);
            let q = UnitQuaternion::from_matrix(&r).into_inner();
            let s = q.w >= 0.0;
            if last_sign.is_some_and(|p| p != s) {
                memoryless_switches += 1;
            }
            last_sign = Some(s);
        }
        assert!(memoryless_switches > 100, "the test noise must cross 180°");
        assert!(l.counters().m_flips <= 1, "flips: {:?}", l.counters());
    }

    #[test]
    fn flip_applies_when_both_conditions_hold() {
        // Memory at identity, error jumps straight to 179°: dist ≈ 1 > α and |ϑ| ≈ 1 too, but
        // after the reset the principal MRP of a 179° rotation is ≈ 0.98 < 1 + δ: one reset.
        let mut l = PathLifting::new(0.02, 0.25);
        l.lift(&Matrix3::identity());
        let out = l.lift(&rot(Vector3::y(), 179f64.to_radians()));
        assert_eq!(out.jumps.q_hat_resets, 1);
        assert!(out.mrp.norm() <= 1.02);
        // Now continue past 180° with the memory following: |ϑ| grows past 1 + δ, m* flips.
        let mut flipped = 0;
        for k in 0..40 {
            let angle = (179.0 + k as f64).to_radians();
            let out = l.lift(&rot(Vector3::y(), angle));
            flipped += out.jumps.m_flips;
            assert!(out.mrp.norm() <= 1.02 + 1e-12);
            let q = rotation_from_quaternion(&out.quaternion);
            assert_relative_eq!(q, rot(Vector3::y(), angle), epsilon = 1e-9);
        }
        assert_eq!(flipped, 1);
    }
}
