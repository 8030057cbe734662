//! A compensated heading for the desired attitude: the desired frame's yaw rate is the
//! compensator's alone (extension of Lemma 1 / eq:DesiredRotationMatrix).
//!
//! The paper builds `R_d = [υ, ρ × υ, ρ]` from the thrust direction `ρ = u/|u|` and a heading
//! `ν = (cos ψ, sin ψ)` (eq:DesiredRotationMatrix). With `n = (ν, 0)`, `k = n × e₃ =
//! (sin ψ, −cos ψ, 0)` (horizontal, across the heading), `s = ρᵀk`, `|ϖ|² = 1 − s²` and
//! `D = det(ρ, ρ̇, k) = ρ·(ρ̇ × k)`, the desired frame's yaw rate is
//! ([`crate::desired_frame_bounds`], checked against [`desired_attitude`] by its tests and by this
//! module's)
//!
//! `ω_d,3 = (s D + ψ̇ ρ₃)/|ϖ|²`.
//!
//! Fed the reference heading `ψ_d`, the frame yaws whenever the thrust direction tilts across the
//! heading (`s D ≠ 0`), and `ω̇_d,3` then holds `s det(ρ, ρ̈, k)/|ϖ|²`: a term in `ρ̈`, which on a
//! vehicle with little yaw torque caps how fast the position loop's filters may be. Here the
//! construction is fed a controller state `ψ_c` instead, whose rate cancels that coupling:
//!
//! - `ψ̇_c = c − s D/ρ₃`, with `k`, `s`, `D` taken at `ψ_c`, and
//! - `c = ψ̇_d + L tanh(k_ψ sin(ψ_d − ψ_c)/L)` (`L > 0` the level [rad/s], `k_ψ > 0` the gain
//!   [1/s], [`HeadingCompensatorGains`]),
//!
//! so that `ω_d,3 = c ρ₃/|ϖ|²` exactly: the frame's yaw rate is the commanded rate `c` alone,
//! bounded by design, and `ω̇_d,3` holds no `ρ̈` (only `ċ`, `ρ̇₃` and `ṡ`). The sign is the one
//! of [`desired_attitude`]'s `ω_d` (desired body frame) with `k = n × e₃`; the tests check the
//! identity against the law itself.
//!
//! The feedforward `ψ̈_c` in closed form: `dk/dψ = n`, so `k̇ = ψ̇_c n`,
//! `ṡ = ρ̇ᵀk + ψ̇_c ρᵀn`, `Ḋ = det(ρ, ρ̈, k) + ψ̇_c det(ρ, ρ̇, n)`,
//! `ċ = ψ̈_d + σ' k_ψ cos(ψ_d − ψ_c)(ψ̇_d − ψ̇_c)` with `σ' = 1 − tanh²(k_ψ sin(ψ_d − ψ_c)/L)`
//! ([`crate::saturation::tanh_saturation_slope`]), and
//!
//! `ψ̈_c = ċ − (ṡ D + s Ḋ)/ρ₃ + s D ρ̇₃/ρ₃²`.
//!
//! With `ρ` and `ψ_d` constant, `D = 0` and `ė = −L tanh(k_ψ sin e/L)` for `e = ψ_d − ψ_c`:
//! every start but the unstable equilibrium `e = π` converges to `e = 0`, since
//! `d/dt ln|tan(e/2)| = ė/sin e = −L tanh(k_ψ sin e/L)/sin e` lies in `[−k_ψ, −κ]`,
//! `κ = L tanh(k_ψ/L)` (`tanh(a x)/x` decreases in `|x|`): `|tan(e/2)|` shrinks at least as
//! `exp(−κ t)` and at most as `exp(−k_ψ t)`.
//!
//! `ψ̈_c` itself holds `ρ̈` (through `Ḋ`): `ν̈_c` carries it into `ϋ`, where it cancels the
//! tilt's own term. So a bound on `|ν̈_c|` (Lemma 1's `K_ν̈` slot) would hold `ρ̈`; the yaw bounds
//! below do not, and the tilt components `(ω̇_d,1, ω̇_d,2)` read no heading acceleration
//! ([`crate::desired_frame_bounds`]).
//!
//! Bounds ([`yaw_bounds`]) for the certificate, with `|ρ̇| ≤ U_ρ̇`, `|ρ_xy| ≤ h`, `ρ₃ ≥ L_ϖ`,
//! `|ψ̇_d| ≤ K_ν̇`, `|ψ̈_d| ≤ K_ν̈` ([`CompensatorChain`]); each step:
//!
//! - `|ϖ|² = ρ₃² + (ρᵀn)²`, so `L_ϖ ≤ ρ₃ ≤ |ϖ| ≤ 1`; `|s| ≤ |ρ_xy| ≤ h` and `|ρᵀn| ≤ h`;
//! - `D = ρ̇ᵀ(k × ρ)` and `|k × ρ| = |ϖ|`, so `|D| ≤ U_ρ̇`;
//! - `ρ̇ ⊥ ρ`, so `ρ̇₃ = ρ̇ᵀ(e₃ − ρ₃ ρ)` with `|e₃ − ρ₃ ρ| = |ρ_xy|`: `|ρ̇₃| ≤ h U_ρ̇`;
//! - `|c| ≤ K_ν̇ + L`; `|ψ̇_c| ≤ U_ψc := K_ν̇ + L + h U_ρ̇/L_ϖ` ([`heading_rate_bound`]);
//! - `ψ̇_d − ψ̇_c = −L tanh(·) + s D/ρ₃`, so `|ċ| ≤ C' := K_ν̈ + k_ψ (L + h U_ρ̇/L_ϖ)`
//!   (`σ' ≤ 1`);
//! - `|ṡ| ≤ U_ρ̇ + h U_ψc`;
//! - `|ω_d,3| = |c| ρ₃/|ϖ|² ≤ |c|/|ϖ| ≤ (K_ν̇ + L)/L_ϖ`;
//! - `ω̇_d,3 = ċ ρ₃/|ϖ|² + c ρ̇₃/|ϖ|² + 2 c ρ₃ s ṡ/|ϖ|⁴`, so
//!   `|ω̇_d,3| ≤ C'/L_ϖ + (K_ν̇ + L) h U_ρ̇/L_ϖ² + 2 (K_ν̇ + L) h (U_ρ̇ + h U_ψc)/L_ϖ³`.
//!
//! No term holds `ρ̈`. The controller flies it when [`crate::Gains::heading_compensator`] is
//! set (its state `ψ_c` starts at `ψ_d`), and `certify` then takes the desired frame's yaw
//! bounds from [`yaw_bounds`] (docs/heading-compensator.md).
//!
//! [`desired_attitude`]: crate::desired_attitude::desired_attitude

use nalgebra::{Vector2, Vector3};

use crate::desired_attitude::UnitWithDerivatives;
use crate::parameter_error::{positive, ParameterError};
use crate::scalar::{lit, Scalar};

/// Gains of the heading compensator (extension, module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeadingCompensatorGains<T: Scalar> {
    /// `L` [rad/s]: the level of the heading feedback `L tanh(k_ψ sin(ψ_d − ψ_c)/L)`, so the
    /// commanded rate `c` lies within `L` of `ψ̇_d`.
    pub level: T,
    /// `k_ψ` [1/s]: the feedback's slope at `ψ_c = ψ_d` (the linear convergence rate).
    pub gain: T,
}

impl<T: Scalar> HeadingCompensatorGains<T> {
    /// Checks that `L` and `k_ψ` are finite and `> 0`.
    /// Errors: [`ParameterError::NotPositive`] naming the first offender (`"L_psi"`, then
    /// `"k_psi"`).
    pub fn validate(&self) -> Result<(), ParameterError> {
        positive("L_psi", self.level)?;
        positive("k_psi", self.gain)
    }
}

/// The compensated heading at one sample: the angle, its two derivatives and the unit vector
/// `ν_c` with its two derivatives, as [`desired_attitude`] takes its heading.
///
/// [`desired_attitude`]: crate::desired_attitude::desired_attitude
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CompensatedHeading<T: Scalar> {
    /// `ψ_c` \[rad\], as given (the compensator's state; [`advance`] keeps it in `(−π, π]`).
    pub angle: T,
    /// `ψ̇_c = c − s D/ρ₃` [rad/s].
    pub rate: T,
    /// `ψ̈_c` [rad/s²] (module documentation).
    pub acceleration: T,
    /// `c = ψ̇_d + L tanh(k_ψ sin(ψ_d − ψ_c)/L)` [rad/s]: the commanded rate, with
    /// `ω_d,3 = c ρ₃/|ϖ|²`.
    pub commanded_rate: T,
    /// `ν_c = (cos ψ_c, sin ψ_c)` (inertial horizontal plane, unit).
    pub heading: Vector2<T>,
    /// `ν̇_c = ψ̇_c (−sin ψ_c, cos ψ_c)` [1/s].
    pub heading_rate: Vector2<T>,
    /// `ν̈_c = ψ̈_c (−sin ψ_c, cos ψ_c) − ψ̇_c² ν_c` [1/s²].
    pub heading_acceleration: Vector2<T>,
}

/// The compensated heading's rate and acceleration at the state `heading` (`ψ_c` \[rad\]) for the
/// thrust direction `ρ` with `ρ̇` [1/s], `ρ̈` [1/s²] (inertial, from
/// [`normalize_with_derivatives`]) and the reference heading `reference = (ψ_d \[rad\], ψ̇_d
/// [rad/s], ψ̈_d [rad/s²])`.
///
/// Pure: the closed forms of the module documentation. Any angle is accepted (only its sine and
/// cosine enter). Requires `ρ₃ > 0`, which [`desired_attitude`] checks before it uses the result;
/// at `ρ₃ = 0` the rates are not finite, at `ρ₃ < 0` they are finite but meaningless. No errors;
/// the gains are assumed valid
/// ([`HeadingCompensatorGains::validate`]).
/// Source: extension of Lemma 1 / eq:DesiredRotationMatrix (module documentation).
///
/// [`desired_attitude`]: crate::desired_attitude::desired_attitude
/// [`normalize_with_derivatives`]: crate::desired_attitude::normalize_with_derivatives
pub fn compensated_heading<T: Scalar>(
    gains: &HeadingCompensatorGains<T>,
    heading: T,
    thrust_direction: &UnitWithDerivatives<T>,
    reference: (T, T, T),
) -> CompensatedHeading<T> {
    let (psi_d, psi_d_rate, psi_d_acceleration) = reference;
    let (r, rd, rdd) = (
        &thrust_direction.unit,
        &thrust_direction.rate,
        &thrust_direction.acceleration,
    );
    let (sin, cos) = heading.sin_cos();
    // n along the heading; k = n × e₃ across it, and dk/dψ = n.
    let n = Vector3::new(cos, sin, T::zero());
    let k = Vector3::new(sin, -cos, T::zero());
    let s = r.dot(&k);
    let det = r.dot(&rd.cross(&k));

    let (error_sin, error_cos) = (psi_d - heading).sin_cos();
    let t = (gains.gain * error_sin / gains.level).tanh();
    let commanded_rate = psi_d_rate + gains.level * t;
    let rate = commanded_rate - s * det / r.z;

    // 1 − t² is tanh_saturation_slope at k_ψ sin(ψ_d − ψ_c), without a second tanh.
    let commanded_acceleration =
        psi_d_acceleration + (T::one() - t * t) * gains.gain * error_cos * (psi_d_rate - rate);
    let s_rate = rd.dot(&k) + rate * r.dot(&n);
    let det_rate = r.dot(&rdd.cross(&k)) + rate * r.dot(&rd.cross(&n));
    let acceleration =
        commanded_acceleration - (s_rate * det + s * det_rate) / r.z + s * det * rd.z / (r.z * r.z);

    let nu = Vector2::new(cos, sin);
    let perp = Vector2::new(-sin, cos);
    CompensatedHeading {
        angle: heading,
        rate,
        acceleration,
        commanded_rate,
        heading: nu,
        heading_rate: perp * rate,
        heading_acceleration: perp * acceleration - nu * (rate * rate),
    }
}

/// One explicit (forward Euler) step of the compensator's state: `ψ_c + ψ̇_c dt` wrapped to
/// `(−π, π]` \[rad\], from `heading` `ψ_c` \[rad\], `rate` `ψ̇_c` [rad/s] and the step `dt` \[s\].
///
/// Wrapping changes nothing downstream (only `sin ψ_c`, `cos ψ_c` enter the law); it keeps the
/// state's magnitude, and so its rounding, bounded over a long flight. No errors; a non-finite
/// input gives a non-finite result. Source: extension (module documentation).
pub fn advance<T: Scalar>(heading: T, rate: T, dt: T) -> T {
    wrap_angle(heading + rate * dt)
}

/// `x` wrapped to `(−π, π]` \[rad\].
fn wrap_angle<T: Scalar>(x: T) -> T {
    let pi = T::pi();
    let two_pi = T::two_pi();
    // x − 2π⌊(x + π)/2π⌋ lies in [−π, π) up to rounding; the two guards move the ends (and a
    // rounding just outside) into (−π, π].
    let mut y = x - two_pi * ((x + pi) / two_pi).floor();
    if y <= -pi {
        y += two_pi;
    }
    if y > pi {
        y -= two_pi;
    }
    y
}

/// What the compensated frame's yaw bounds are computed from: Lemma 1's chain and Assumption 1's
/// heading constants (module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CompensatorChain<T: Scalar> {
    /// `U_ρ̇` [1/s]: bound on `|ρ̇|` (Lemma 1).
    pub thrust_direction_rate: T,
    /// `h` (dimensionless): bound on the horizontal share `|ρ_xy|` of the thrust direction, in
    /// `[0, 1)` (`√(1 − L_ϖ²)` with Lemma 1's `L_ϖ`).
    pub horizontal_share: T,
    /// `L_ϖ` (dimensionless): lower bound of `ρ₃` (and so of `|ϖ|`), in `(0, 1]` (Lemma 1).
    pub heading_projection_min: T,
    /// `K_ν̇` [rad/s]: bound on `|ψ̇_d|` (Assumption 1).
    pub heading_rate: T,
    /// `K_ν̈` [rad/s²]: bound on `|ψ̈_d|` (Assumption 1 bounds `|ν̈_d| ≥ |ψ̈_d|`).
    pub heading_acceleration: T,
}

/// `U_ψc = K_ν̇ + L + h U_ρ̇/L_ϖ` [rad/s]: bound on the compensated heading's rate `|ψ̇_c|`
/// (module documentation). No errors; the chain is assumed as documented
/// ([`CompensatorChain`]). Source: extension of Lemma 1.
pub fn heading_rate_bound<T: Scalar>(
    gains: &HeadingCompensatorGains<T>,
    chain: &CompensatorChain<T>,
) -> T {
    let c = chain;
    c.heading_rate
        + gains.level
        + c.horizontal_share * c.thrust_direction_rate / c.heading_projection_min
}

/// `(U_ω3, U_ω̇3)`: bounds on `|ω_d,3|` [rad/s] and `|ω̇_d,3|` [rad/s²], the yaw components
/// (desired body frame) of the angular velocity and acceleration of the frame built from the
/// compensated heading ([`compensated_heading`] fed to [`desired_attitude`]):
///
/// - `U_ω3 = (K_ν̇ + L)/L_ϖ`,
/// - `U_ω̇3 = (K_ν̈ + k_ψ (L + h U_ρ̇/L_ϖ))/L_ϖ + (K_ν̇ + L) h U_ρ̇/L_ϖ²
///   + 2 (K_ν̇ + L) h (U_ρ̇ + h U_ψc)/L_ϖ³`,
///
/// with `U_ψc` from [`heading_rate_bound`] (derivation in the module documentation). No term in
/// `ρ̈`: however violent the thrust direction's acceleration, the frame's yaw acceleration stays
/// below `U_ω̇3`. No errors; the chain is assumed as documented ([`CompensatorChain`]).
/// Source: extension of Lemma 1 / eq:DesiredRotationMatrix.
///
/// [`desired_attitude`]: crate::desired_attitude::desired_attitude
pub fn yaw_bounds<T: Scalar>(
    gains: &HeadingCompensatorGains<T>,
    chain: &CompensatorChain<T>,
) -> (T, T) {
    let c = chain;
    let (rate, h, l) = (
        c.thrust_direction_rate,
        c.horizontal_share,
        c.heading_projection_min,
    );
    let commanded = c.heading_rate + gains.level;
    let commanded_acceleration = c.heading_acceleration + gains.gain * (gains.level + h * rate / l);
    let heading_rate = heading_rate_bound(gains, chain);
    let yaw_rate = commanded / l;
    let yaw_acceleration = commanded_acceleration / l
        + commanded * h * rate / (l * l)
        + lit::<T>(2.0) * commanded * h * (rate + h * heading_rate) / (l * l * l);
    (yaw_rate, yaw_acceleration)
}

#[cfg(test)]
mod tests;
