//! `ω_d` and `ω̇_d` as one generic expression, for points, intervals and gradients.
//!
//! The same formulas, in the same order, as `controller_core::desired_attitude`
//! (eq:DesiredRotationMatrix, eq:DesiredAngularVelocity, eq:DesiredAngularAcceleration, the
//! proof of Lemma 1): `ρ = u/|u|` with `ρ̇`, `ρ̈`; `ϖ = (ρ₃ν, −ρᵀν*)` (the branch `ρ₃ > 0`,
//! which holds on the whole confining set because `u₃ ≥ g − M_p − K_a3 > 0`) with `ϖ̇`, `ϖ̈`;
//! `υ = ϖ/|ϖ|` with `υ̇`, `ϋ`; `R_d = [υ, ρ × υ, ρ]`. The heading is parametrised by its angle:
//! `ν_d = (cos ψ, sin ψ)`, `ν̇_d = ψ̇ ν⊥`, `ν̈_d = ψ̈ ν⊥ − ψ̇² ν` with `ν⊥ = (−sin ψ, cos ψ)`
//! (every unit heading signal has this form). Evaluated on `f64` it must agree with
//! controller-core to rounding (tested in `host-sim/tests/tight_bounds.rs`); on
//! [`super::interval::Interval`] or [`super::gradient::Gradient`] it gives rigorous
//! enclosures over a box.

use super::arith::{add, cross, dot, norm_squared, scale, sub, Arith, V3};

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

/// `(y, ẏ, ÿ)` for `y = x/|x|`: `ẏ = (I − yyᵀ)ẋ/|x|`,
/// `ÿ = (I − yyᵀ)ẍ/|x| − 2 (yᵀẋ)/|x| ẏ − |ẏ|² y` (as `normalize_with_derivatives`).
fn normalize<T: Arith>(x: &V3<T>, x_dot: &V3<T>, x_ddot: &V3<T>) -> [V3<T>; 3] {
    let n = norm_squared(x).sqrt();
    let y = x.map(|c| c / n);
    let project = |v: &V3<T>| sub(v, &scale(&y, dot(&y, v)));
    let rate = project(x_dot).map(|c| c / n);
    let radial_rate = dot(&y, x_dot) / n;
    let acceleration = sub(
        &sub(
            &project(x_ddot).map(|c| c / n),
            &scale(&rate, T::constant(2.0) * radial_rate),
        ),
        &scale(&y, norm_squared(&rate)),
    );
    [y, rate, acceleration]
}

/// `ω_d`, `ω̇_d` from the control vector `u` [m/s²] with `u̇`, `ü` (inertial) and the heading.
///
/// Precondition (not checked): `|u| > 0` and `u₃ > 0`; on intervals, a violation only makes
/// the enclosure the whole line. Source: eq:DesiredRotationMatrix,
/// eq:DesiredAngularVelocity, eq:DesiredAngularAcceleration (as in
/// `controller_core::desired_attitude`).
pub fn desired_rates<T: Arith>(
    u: &V3<T>,
    u_dot: &V3<T>,
    u_ddot: &V3<T>,
    heading: &Heading<T>,
) -> Rates<T> {
    let [r, rd, rdd] = normalize(u, u_dot, u_ddot);
    let zero = T::constant(0.0);
    let two = T::constant(2.0);
    let (c, s, w, a) = (heading.cos, heading.sin, heading.rate, heading.acceleration);
    let nu = [c, s, zero];
    let perp = [-s, c, zero];
    let nu_d = scale(&perp, w);
    let nu_dd = sub(&scale(&perp, a), &scale(&nu, w.sqr()));
    // ϖ = (ρ₃ν, −ρᵀν*) and its derivatives by the product rule.
    let varpi_of = |h: V3<T>, v: T| [h[0], h[1], -v];
    let varpi = varpi_of(scale(&nu, r[2]), dot(&r, &nu));
    let varpi_dot = varpi_of(
        add(&scale(&nu, rd[2]), &scale(&nu_d, r[2])),
        dot(&rd, &nu) + dot(&r, &nu_d),
    );
    let varpi_ddot = varpi_of(
        add(
            &add(&scale(&nu, rdd[2]), &scale(&nu_d, two * rd[2])),
            &scale(&nu_dd, r[2]),
        ),
        dot(&rdd, &nu) + two * dot(&rd, &nu_d) + dot(&r, &nu_dd),
    );
    let [y, yd, ydd] = normalize(&varpi, &varpi_dot, &varpi_ddot);
    let second = cross(&r, &y);
    let omega = [-dot(&rd, &second), dot(&y, &rd), dot(&yd, &second)];
    let gyro = [
        omega[1] * omega[2],
        -(omega[0] * omega[2]),
        -(omega[0] * omega[1]),
    ];
    let omega_dot = add(
        &gyro,
        &[-dot(&rdd, &second), dot(&y, &rdd), dot(&ydd, &second)],
    );
    Rates {
        angular_velocity: omega,
        angular_acceleration: omega_dot,
    }
}
