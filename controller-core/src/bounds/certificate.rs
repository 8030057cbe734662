//! What [`super::certify`] returns: the bounds, the conditions with both sides of each
//! inequality, and where the filters start (an input of Lemma 1).

use nalgebra::Vector3;

use crate::attitude_energy::EnergyLimits;
use crate::condition::{Condition, Violation};
use crate::desired_frame_bounds::DesiredFrameBounds;
use crate::integral_stability::STABILITY_CONDITION_COUNT;
use crate::scalar::{to_f64, Scalar};
use crate::torque_set::TorqueSet;

/// Where the filter states start; Lemma 1's `U_l` depends on it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FilterStart {
    /// `x_f(0) = 0` (Section VI): `U_l = (k_f/k_s)^{k_f/(k_s−k_f)}` (`e⁻¹` if `k_f = k_s`).
    Zero,
    /// Any `x_f(0) ∈ M_p 𝔹⁶_∞`: `U_l = 1`. With the norm shape of `σ_p`, `u_f(0)` and `u_s(0)`
    /// each in the ball `M_p 𝔹³` (where the law keeps them; docs/position-saturation.md).
    InSaturationBox,
}

/// The bounds of Lemma 1 evaluated with the Assumption 1 constants (`U*` quantities).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AssumptionBounds<T: Scalar> {
    /// `U*_ρ̇ = K_j/(g − K_a3)` [1/s].
    pub thrust_direction_rate: T,
    /// `U*_ρ̈ = K_s/(g − K_a3) + 3U*_ρ̇²` [1/s²].
    pub thrust_direction_acceleration: T,
    /// `L* = (g − K_a3)/sqrt(K_a12² + (g − K_a3)²)`.
    pub heading_projection_min: T,
    /// `U*_υ̇` [1/s].
    pub heading_axis_rate: T,
    /// `U*_ϋ` [1/s²].
    pub heading_axis_acceleration: T,
    /// `U*_ωd = sqrt(U*_ρ̇² + U*_υ̇²)` [rad/s].
    pub angular_velocity: T,
    /// `U*_ω̇d = U*_ρ̇ U*_υ̇ + sqrt(U*_ρ̈² + U*_ϋ²)` [rad/s²].
    pub angular_acceleration: T,
}

/// Every bound of the paper for one set-up.
///
/// With the integral action on ([`Gains::integral`](crate::Gains::integral)), `L = M_p + M_i` per axis and the bounds
/// are the extended ones (extension, docs/integral-action.md), as noted per field.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds<T: Scalar> {
    /// `T_min = m(g − M_p − K_a3)` \[N\] (eq:LowerBoundT); with the integral action
    /// `m(g − K_a3 − L_z)`.
    pub thrust_min: T,
    /// `T_max = m(√3 M_p + sqrt(K_a12² + (K_a3 + g)²))` \[N\] (eq:UpperBoundT); with the integral
    /// action `m sqrt((sqrt(L_x² + L_y²) + K_a12)² + (g + K_a3 + L_z)²)`. With the norm shape of
    /// `σ_p` ([`PositionSaturation::Norm`](crate::PositionSaturation::Norm)) `M_p` replaces `√3 M_p`, and with the integral action
    /// `m(M_p + sqrt((|M_i,xy| + K_a12)² + (g + K_a3 + M_i,z)²))`.
    ///
    /// With the envelope design's local regime, [`certify`](super::certify) widens `thrust_min` and
    /// `thrust_max` to the hull of both regimes' intervals (the local one is
    /// `LocalCertificate::bounds`'): every thrust the law asks for, the interval the rotor fits
    /// and the thrust floor are checked on. The `theorem1.*` conditions are the global gains';
    /// `local_regime.*` the local ones'.
    pub thrust_max: T,
    /// `U_l` of Lemma 1 (dimensionless).
    pub filter_overshoot: T,
    /// `U_u̇ = 2√3 k_f U_l M_p + K_j` [m/s³] (`2 k_f U_l M_p + K_j` with the norm shape); with
    /// the integral action `+ |b|`, `b_i =
    /// min(2 k_η M_i,i, c R_i,i)` the reachable-set bound on `|η̇_f,i|`
    /// (`IntegralGains::filtered_rate_bound`).
    pub u_rate: T,
    /// `U_ü = 2√3 k_f M_p (k_f U_l + k_s) + K_s` [m/s⁴] (`2 k_f M_p (k_f U_l + k_s) + K_s` with
    /// the norm shape); with the integral action
    /// `+ k_η |b + R_i|` (`IntegralGains::filtered_acceleration_bound`).
    pub u_acceleration: T,
    /// `U_ρ̇ = m U_u̇ / T_min` [1/s].
    pub thrust_direction_rate: T,
    /// `U_ρ̈ = m U_ü / T_min + 3 U_ρ̇²` [1/s²], the bound on `|ρ̈|`; with
    /// [`crate::Lemma1Form::Tangential`] `m U_ü / T_min + (2/√3) U_ρ̇²` (reported; the chain
    /// uses the projected bound below).
    pub thrust_direction_acceleration: T,
    /// The bound on the part of `ρ̈` orthogonal to `ρ`, the only part eq:DesiredAngularAcceleration
    /// reads [1/s²]: `U_ρ̈` itself with [`crate::Lemma1Form::Paper`], `m U_ü / T_min + U_ρ̇²` with
    /// [`crate::Lemma1Form::Tangential`] (docs/tangential-lemma1.md).
    pub thrust_direction_acceleration_projected: T,
    /// `L_ϖ`, lower bound of `|ϖ|` (dimensionless); the horizontal part of `u_f` is at most
    /// `√2 M_p` (`M_p` with the norm shape).
    pub heading_projection_min: T,
    /// `U_υ̇ = (U_ρ̇ + K_ν̇)/L_ϖ` [1/s].
    pub heading_axis_rate: T,
    /// `U_ϋ = (U_ρ̈ + 2U_ρ̇K_ν̇ + K_ν̈)/L_ϖ + 3U_υ̇²` [1/s²]; with [`crate::Lemma1Form::Tangential`]
    /// the projected `U_ρ̈` and `+ U_υ̇²`: the bound on the part of `ϋ` orthogonal to `υ` (all
    /// that eq:DesiredAngularAcceleration reads).
    pub heading_axis_acceleration: T,
    /// `U_ωd = sqrt(U_ρ̇² + U_υ̇²)` [rad/s] (Lemma 1).
    pub angular_velocity: T,
    /// `U_ω̇d = U_ρ̇ U_υ̇ + sqrt(U_ρ̈² + U_ϋ²)` [rad/s²] (Lemma 1); with
    /// [`crate::Lemma1Form::Tangential`] the projected `U_ρ̈` in place of `U_ρ̈`.
    pub angular_acceleration: T,
    /// `ι = (1 + (1 + δ)²) M_ϑ/4 + M_ω` [N m]: bound of the saturated feedback per axis; with
    /// tilt priority the largest of [`Bounds::feedback_torque_axes`].
    pub feedback_torque: T,
    /// Per-axis feedback bound `ι_i` [N m], body axes: `ι` on every axis for the paper's law,
    /// [`crate::TiltPriorityGains::feedback_levels`] with tilt priority.
    pub feedback_torque_axes: Vector3<T>,
    /// Per-axis torque bound `J_ii U_ω̇d + ½|J_jj − J_kk| U_ωd² + ι_i` [N m] (Theorem 2), with
    /// Lemma 1's norms, or with [`crate::Lemma1Form::DesiredFrame`] the torque set's norms (then
    /// it is the set's extent along each axis).
    pub torque_max: Vector3<T>,
    /// The set the torque stays in, with its shape (ellipsoid, boxes and ball; extension of
    /// Theorem 2, [`crate::torque_set`]); its per-axis extents are at most [`Bounds::torque_max`]
    /// (equal with [`crate::Lemma1Form::DesiredFrame`]).
    pub torque_set: TorqueSet<T>,
    /// The `U*` bounds of Assumption 1.
    pub assumption: AssumptionBounds<T>,
    /// Lemma 1 per axis of the desired frame: bounds on the tilt and yaw components of `ω_d`,
    /// `ω̇_d` and of the gyroscopic term (extension, [`crate::desired_frame_bounds`]).
    pub desired_frame: DesiredFrameBounds<T>,
    /// The feedforward's set with the body frame on the desired frame (`R̃ = I`, no
    /// feedback; [`DesiredFrameBounds::aligned_feedforward`]): what airmode's convergence
    /// argument needs to fit the thrust interval (docs/airmode.md).
    pub aligned_feedforward: TorqueSet<T>,
}

/// Number of conditions checked.
pub const CONDITION_COUNT: usize = 10;

/// What the integral action adds to the certificate (extension, docs/integral-action.md).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IntegralCertificate<T: Scalar> {
    /// `L = M_p + M_i` [m/s²] per inertial axis: the bound on `|u_f,i + η_f,i|`.
    pub level_sum: Vector3<T>,
    /// `2 k_η |M_i|` [m/s³], the term added to `U_u̇`.
    pub u_rate_term: T,
    /// `k_η (2 k_η |M_i| + |R_i|)` [m/s⁴], the term added to `U_ü`.
    pub u_acceleration_term: T,
    /// `[a₀, …, a₅]` of the per-axis linearisation's characteristic polynomial, ascending
    /// (the quartic's `a₅ = 0`; [`crate::integral_stability::characteristic_polynomial`]).
    pub polynomial: [T; 6],
    /// The Routh–Hurwitz conditions for local exponential stability.
    pub conditions: [Condition<T>; STABILITY_CONDITION_COUNT],
}

/// The bounds and the conditions for one set-up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Certificate<T: Scalar> {
    /// Every bound.
    pub bounds: Bounds<T>,
    /// Every condition, in the order of the paper (extended where the integral action is on).
    pub conditions: [Condition<T>; CONDITION_COUNT],
    /// The integral action's terms and conditions; `None` when it is off.
    pub integral: Option<IntegralCertificate<T>>,
    /// Tilt priority's hysteresis-band condition ([`crate::TiltPriorityGains::hysteresis_band`]);
    /// `None` when it is off.
    pub tilt_priority: Option<[Condition<T>; 1]>,
    /// The envelope design's local regime ([`LocalCertificate`]); `None` when it is off.
    pub local: Option<LocalCertificate<T>>,
}

impl<T: Scalar> Certificate<T> {
    /// `Ok` if every condition holds; otherwise the first violated one as an error value.
    pub fn require_feasible(&self) -> Result<(), Violation> {
        match self.violations().next() {
            None => Ok(()),
            Some(c) => Err(Violation {
                name: c.name,
                statement: c.statement,
                lhs: to_f64(c.lhs),
                rhs: to_f64(c.rhs),
            }),
        }
    }

    /// The violated conditions (the paper's, then the extensions').
    pub fn violations(&self) -> impl Iterator<Item = &Condition<T>> {
        self.all_conditions().filter(|c| !c.holds)
    }

    /// Every condition: the paper's, then the integral action's and tilt priority's when on.
    pub fn all_conditions(&self) -> impl Iterator<Item = &Condition<T>> {
        let extra: &[Condition<T>] = match &self.integral {
            Some(i) => &i.conditions,
            None => &[],
        };
        let tilt: &[Condition<T>] = match &self.tilt_priority {
            Some(c) => c,
            None => &[],
        };
        let local: &[Condition<T>] = match &self.local {
            Some(l) => &l.conditions,
            None => &[],
        };
        self.conditions
            .iter()
            .chain(extra.iter())
            .chain(tilt.iter())
            .chain(local.iter())
    }

    /// Per-axis bound [N m] of every torque the law applies: Theorem 2's, or with the envelope
    /// design the larger of it and the local regime's extent (body axes).
    pub fn torque_max_all(&self) -> Vector3<T> {
        match &self.local {
            None => self.bounds.torque_max,
            Some(l) => self.bounds.torque_max.sup(&l.torque_set.axis_extents()),
        }
    }
}

/// What the local regime adds to the certificate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LocalCertificate<T: Scalar> {
    /// Every bound of the law with the local position gains, the filters anywhere in the
    /// saturation set (Lemma 1's `U_l = 1`: the regime starts from wherever the global one left
    /// them).
    pub bounds: Bounds<T>,
    /// The attitude error's bounds inside `{E ≤ E_out}`.
    pub energy: EnergyLimits<T>,
    /// The local regime's torque set [N m], body frame: the feedback at the attitude errors of
    /// [`LocalCertificate::energy`] and the local feedforward turned by at most their rotation
    /// ([`super::local_torque_set`]).
    pub torque_set: TorqueSet<T>,
    /// `τ_max,i >` the set's extent on body axis `i` (`local_regime.torque_max_*`), then
    /// Theorem 1's two conditions for the local gains (`local_regime.saturation_margin`: the
    /// local thrust floor is positive; `local_regime.thrust_bound_within_actuator`: the local
    /// `T_max` within the rotors'), which matter once `M_p,L` exceeds `M_p`.
    pub conditions: [Condition<T>; LOCAL_CONDITION_COUNT],
}

/// Number of the local regime's conditions.
pub const LOCAL_CONDITION_COUNT: usize = 5;
