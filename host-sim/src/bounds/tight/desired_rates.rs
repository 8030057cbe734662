//! `ω_d` and `ω̇_d` in closed form in the desired body frame, for points, intervals and
//! gradients.
//!
//! controller-core computes `ω_d`, `ω̇_d` by normalising `u` and `ϖ` and differentiating twice
//! (eq:DesiredRotationMatrix, eq:DesiredAngularVelocity, eq:DesiredAngularAcceleration). The
//! same values follow from a shorter chain, which interval arithmetic encloses far more tightly
//! (fewer repeated occurrences of the same variable):
//!
//! Let `n = |u|`, `ρ = u/n`, `ν* = (cos ψ, sin ψ, 0)`, `w = ν* × e₃ = (sin ψ, −cos ψ, 0)`,
//! `μ = ρ·ν*`, `σ = ρ·w`, `c = √(ρ₃² + μ²)` (`ρ₃² + μ² + σ² = 1`). Then `ϖ = ρ × w`, `|ϖ| = c`,
//! `υ = (ρ₃ cos ψ, ρ₃ sin ψ, −μ)/c`, `s = ρ × υ = (σρ − w)/c`, and with the body-frame components
//! `α = (υ, s, ρ)ᵀu̇/n`, `β = (υ, s, ρ)ᵀü/n`:
//! - `ω_d = (−α₂, α₁, ω₃)`, `ω₃ = υ̇·s = ϖ̇·s/c = (−α₁σ + ψ̇ρ₃/c)/c`
//!   (`ϖ̇ = ρ̇ × w + ψ̇ ρ × ν*`, `ρ̇ = α₁υ + α₂s`, `ν*·υ = ρ₃/c`);
//! - `ω̇_d` is the time derivative of the body-frame `ω_d` (controller-core's test checks this
//!   against differences of `R_d`). With `υ̇ = ω₃s − ω₂ρ`, `ṡ = −ω₃υ + ω₁ρ`, `ṅ/n = α₃`:
//!   `α̇₁ = ω₃α₂ − 2α₁α₃ + β₁`, `α̇₂ = −ω₃α₁ − 2α₂α₃ + β₂`, so `ω̇₁ = −α̇₂`, `ω̇₂ = α̇₁`;
//!   with `σ̇ = −α₂c + ψ̇μ` (`s·w = −c`), `ċ = −σσ̇/c`, `ρ̇₃ = (−α₁μ + α₂σρ₃)/c`:
//!   `ω̇₃ = −α̇₁σ/c − α₁σ̇/c³ + ψ̈ρ₃/c² + ψ̇(ρ̇₃/c² + 2ρ₃σσ̇/c⁴)`.
//!
//! Every unit heading signal has the form `ν_d = (cos ψ, sin ψ)`, `ν̇_d = ψ̇ ν⊥`,
//! `ν̈_d = ψ̈ ν⊥ − ψ̇² ν_d` (`ν⊥ = (−sin ψ, cos ψ)`). The precondition `u₃ > 0` (the branch
//! `sgn(ρ₃) = 1` of `ϖ`) holds on the whole confining set (`u₃ ≥ g − M_p − K_a3 > 0`).
//! Evaluated on `f64` these formulas agree with `controller_core::desired_attitude` to
//! rounding (tested in `host-sim/tests/tight_bounds.rs`), which also checks the derivation.

use super::arith::{cross, dot, norm_squared, Arith, V3};

/// The heading `ν_d = (cos ψ, sin ψ)` and the rate and acceleration of its angle.
#[derive(Clone, Copy, Debug)]
pub struct Heading<T> {
    /// `cos ψ`.
    pub cos: T,
    /// `sin ψ`.
    pub sin: T,
    /// `ψ̇` [rad/s].
    pub rate: T,
    /// `ψ̈` [rad/s²].
    pub acceleration: T,
}

/// `ω_d` [rad/s] and `ω̇_d` [rad/s²], desired body frame.
#[derive(Clone, Copy, Debug)]
pub struct Rates<T> {
    /// `ω_d` (eq:DesiredAngularVelocity).
    pub angular_velocity: V3<T>,
    /// `ω̇_d` (eq:DesiredAngularAcceleration).
    pub angular_acceleration: V3<T>,
}

/// `ω_d`, `ω̇_d` from the control vector `u` [m/s²] with `u̇`, `ü` (inertial) and the heading
/// (module documentation).
///
/// Precondition (not checked): `u₃ > 0`; on intervals, a violation only makes the enclosure the
/// whole line. Source: eq:DesiredRotationMatrix, eq:DesiredAngularVelocity,
/// eq:DesiredAngularAcceleration, rewritten as in the module documentation.
pub fn desired_rates<T: Arith>(
    u: &V3<T>,
    u_dot: &V3<T>,
    u_ddot: &V3<T>,
    heading: &Heading<T>,
) -> Rates<T> {
    let two = T::constant(2.0);
    let one = T::constant(1.0);
    // Reciprocals once, products after: divisions are the costly interval operation.
    let inv_n = one / norm_squared(u).sqrt();
    let rho = u.map(|x| x * inv_n);
    let (cos, sin, rate) = (heading.cos, heading.sin, heading.rate);
    let mu = rho[0] * cos + rho[1] * sin;
    let sigma = rho[0] * sin - rho[1] * cos;
    let c = (rho[2].sqr() + mu.sqr()).sqrt();
    let inv_c = one / c;
    let ups = [rho[2] * cos * inv_c, rho[2] * sin * inv_c, -mu * inv_c];
    let s = cross(&rho, &ups);
    let body = |v: &V3<T>| {
        [
            dot(&ups, v) * inv_n,
            dot(&s, v) * inv_n,
            dot(&rho, v) * inv_n,
        ]
    };
    let a = body(u_dot);
    let b = body(u_ddot);
    let rho3_c = rho[2] * inv_c;
    let sigma_c = sigma * inv_c;
    let w3 = (rate * rho3_c - a[0] * sigma) * inv_c;
    let a1_dot = w3 * a[1] - two * a[0] * a[2] + b[0];
    let a2_dot = b[1] - w3 * a[0] - two * a[1] * a[2];
    let sigma_dot = rate * mu - a[1] * c;
    let rho3_dot = (a[1] * sigma * rho[2] - a[0] * mu) * inv_c;
    let inv_c2 = inv_c.sqr();
    let w3_dot = heading.acceleration * rho3_c * inv_c
        - a1_dot * sigma_c
        - a[0] * sigma_dot * inv_c2 * inv_c
        + rate * (rho3_dot + two * rho3_c * sigma_c * sigma_dot) * inv_c2;
    Rates {
        angular_velocity: [-a[1], a[0], w3],
        angular_acceleration: [-a2_dot, a1_dot, w3_dot],
    }
}
