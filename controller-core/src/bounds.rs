//! A-priori bounds and feasibility conditions: Assumption 1, Theorem 1, Lemma 1, Theorem 2.
//!
//! [`certify`] takes the vehicle, the actuator limits, the gains and the trajectory constants and
//! returns a [`Certificate`]: every bound the paper derives (thrust interval, bounds on `ω_d`,
//! `ω̇_d`, per-axis torque) and every condition with both sides of its inequality. The
//! conditions are sufficient, not necessary: a violated one means the theorems do not
//! guarantee the bounds for this set-up, not that a flight must fail.
//! [`Certificate::require_feasible`] turns the first violated condition into an error value.

use nalgebra::Vector3;

use crate::params::{Gains, Limits, ParameterError, Vehicle};
use crate::reference::TrajectoryConstants;
use crate::scalar::{lit, to_f64, Scalar};

/// Where the filter states start; Lemma 1's `U_l` depends on it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FilterStart {
    /// `x_f(0) = 0` (Section VI): `U_l = (k_f/k_s)^{k_f/(k_s−k_f)}` (`e⁻¹` if `k_f = k_s`).
    Zero,
    /// Any `x_f(0) ∈ M_p 𝔹⁶_∞`: `U_l = 1`.
    InSaturationBox,
}

/// One inequality of the paper, with both sides.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Condition<T: Scalar> {
    /// Stable identifier, e.g. `"theorem2.torque_max_yaw"`.
    pub name: &'static str,
    /// The inequality as written, with the paper's label.
    pub statement: &'static str,
    /// Left-hand side (the larger side when the condition holds).
    pub lhs: T,
    /// Right-hand side.
    pub rhs: T,
    /// Whether `lhs > rhs` (or `lhs ≥ rhs` for non-strict conditions) holds.
    pub holds: bool,
}

/// A violated condition: its name, statement and numbers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Violation {
    /// Identifier of the condition.
    pub name: &'static str,
    /// The inequality as written.
    pub statement: &'static str,
    /// Left-hand side value.
    pub lhs: f64,
    /// Right-hand side value.
    pub rhs: f64,
}

impl core::fmt::Display for Violation {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(
            f,
            "infeasible: {} violated ({}): lhs = {:.6}, rhs = {:.6}",
            self.name, self.statement, self.lhs, self.rhs
        )
    }
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
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds<T: Scalar> {
    /// `T_min = m(g − M_p − K_a3)` \[N\] (eq:LowerBoundT).
    pub thrust_min: T,
    /// `T_max = m(√3 M_p + sqrt(K_a12² + (K_a3 + g)²))` \[N\] (eq:UpperBoundT).
    pub thrust_max: T,
    /// `U_l` of Lemma 1 (dimensionless).
    pub filter_overshoot: T,
    /// `U_u̇ = 2√3 k_f U_l M_p + K_j` [m/s³].
    pub u_rate: T,
    /// `U_ü = 2√3 k_f M_p (k_f U_l + k_s) + K_s` [m/s⁴].
    pub u_acceleration: T,
    /// `U_ρ̇ = m U_u̇ / T_min` [1/s].
    pub thrust_direction_rate: T,
    /// `U_ρ̈ = m U_ü / T_min + 3 U_ρ̇²` [1/s²].
    pub thrust_direction_acceleration: T,
    /// `L_ϖ`, lower bound of `|ϖ|` (dimensionless).
    pub heading_projection_min: T,
    /// `U_υ̇ = (U_ρ̇ + K_ν̇)/L_ϖ` [1/s].
    pub heading_axis_rate: T,
    /// `U_ϋ = (U_ρ̈ + 2U_ρ̇K_ν̇ + K_ν̈)/L_ϖ + 3U_υ̇²` [1/s²].
    pub heading_axis_acceleration: T,
    /// `U_ωd = sqrt(U_ρ̇² + U_υ̇²)` [rad/s] (Lemma 1).
    pub angular_velocity: T,
    /// `U_ω̇d = U_ρ̇ U_υ̇ + sqrt(U_ρ̈² + U_ϋ²)` [rad/s²] (Lemma 1).
    pub angular_acceleration: T,
    /// `ι = (1 + (1 + δ)²) M_ϑ/4 + M_ω` [N m]: bound of the saturated feedback per axis.
    pub feedback_torque: T,
    /// Per-axis torque bound `J_ii U_ω̇d + ½|J_jj − J_kk| U_ωd² + ι` [N m] (Theorem 2).
    pub torque_max: Vector3<T>,
    /// The `U*` bounds of Assumption 1.
    pub assumption: AssumptionBounds<T>,
}

/// Number of conditions checked.
pub const CONDITION_COUNT: usize = 10;

/// The bounds and the conditions for one set-up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Certificate<T: Scalar> {
    /// Every bound.
    pub bounds: Bounds<T>,
    /// Every condition, in the order of the paper.
    pub conditions: [Condition<T>; CONDITION_COUNT],
}

impl<T: Scalar> Certificate<T> {
    /// `Ok` if every condition holds; otherwise the first violated one as an error value.
    pub fn require_feasible(&self) -> Result<(), Violation> {
        match self.conditions.iter().find(|c| !c.holds) {
            None => Ok(()),
            Some(c) => Err(Violation {
                name: c.name,
                statement: c.statement,
                lhs: to_f64(c.lhs),
                rhs: to_f64(c.rhs),
            }),
        }
    }

    /// The violated conditions.
    pub fn violations(&self) -> impl Iterator<Item = &Condition<T>> {
        self.conditions.iter().filter(|c| !c.holds)
    }
}

/// Per-axis `J_ii A + ½|J_jj − J_kk| B²`: the torque needed to follow `ω_d` with `|ω̇_d| ≤ A`,
/// `|ω_d| ≤ B` (the `τ_c` part of Theorem 2 and eq:TorqueMaxCondition).
fn feedforward_torque_bound<T: Scalar>(inertia: &Vector3<T>, accel: T, rate: T) -> Vector3<T> {
    Vector3::from_fn(|i, _| {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        inertia[i] * accel + lit::<T>(0.5) * (inertia[j] - inertia[k]).abs() * rate * rate
    })
}

/// `a < b`, false when either is NaN (so refusals catch NaN too).
pub(crate) fn strictly_less<T: Scalar>(a: T, b: T) -> bool {
    a.partial_cmp(&b) == Some(core::cmp::Ordering::Less)
}

/// Computes every bound and condition of the paper for this set-up.
///
/// Inputs: vehicle (`m` \[kg\], `J` [kg m²], `g` [m/s²]), limits (`T_max` \[N\], `τ_max` [N m]),
/// gains (Table I), trajectory constants (Assumption 1) and where the filters start.
/// Errors: [`ParameterError`] if an input is not positive and finite or `M_p ≥ g − K_a3` makes
/// `T_min ≤ 0` (every later bound divides by it). A violated *feasibility* condition is not an
/// error here: it is reported in the certificate ([`Certificate::require_feasible`]).
/// Source: Assumption 1 (eq:ThrustConditions, eq:TorqueMaxCondition), Theorem 1
/// (eq:BoundsT), Lemma 1, Theorem 2 (eq:TorqueMaxConditionsTheorem).
pub fn certify<T: Scalar>(
    vehicle: &Vehicle<T>,
    limits: &Limits<T>,
    gains: &Gains<T>,
    constants: &TrajectoryConstants<T>,
    filter_start: FilterStart,
) -> Result<Certificate<T>, ParameterError> {
    vehicle.validate()?;
    limits.validate()?;
    gains.validate()?;
    constants.validate()?;
    let (m, g, inertia) = (vehicle.mass, vehicle.gravity, vehicle.inertia);
    let p = &gains.position;
    let (mp, kf, ks) = (p.saturation, p.kf, p.ks);
    let k = constants;
    let (ka12, ka3) = (k.horizontal_acceleration, k.vertical_acceleration);
    if !strictly_less(mp, g - ka3) {
        return Err(ParameterError::SaturationTooLarge {
            saturation: to_f64(mp),
            limit: to_f64(g - ka3),
        });
    }
    let two = lit::<T>(2.0);
    let three = lit::<T>(3.0);
    let sqrt3 = three.sqrt();

    // Theorem 1.
    let thrust_min = m * (g - mp - ka3);
    let thrust_max = m * (sqrt3 * mp + (ka12 * ka12 + (ka3 + g) * (ka3 + g)).sqrt());

    // Lemma 1.
    let filter_overshoot = match filter_start {
        FilterStart::InSaturationBox => T::one(),
        FilterStart::Zero => {
            let r = kf / ks;
            if (T::one() - r).abs() < lit(1e-9) {
                T::one() / T::one().exp()
            } else {
                (r * r.ln() / (T::one() - r)).exp()
            }
        }
    };
    let u_rate = two * sqrt3 * kf * filter_overshoot * mp + k.jerk;
    let u_acceleration = two * sqrt3 * kf * mp * (kf * filter_overshoot + ks) + k.snap;
    let rho_d = m * u_rate / thrust_min;
    let rho_dd = m * u_acceleration / thrust_min + three * rho_d * rho_d;
    let a = thrust_min / m;
    let lateral = two * mp * mp + ka12 * ka12 + two * two.sqrt() * mp * ka12;
    let heading_projection_min = a / (a * a + lateral).sqrt();
    let ups_d = (rho_d + k.heading_rate) / heading_projection_min;
    let ups_dd = (rho_dd + two * rho_d * k.heading_rate + k.heading_acceleration)
        / heading_projection_min
        + three * ups_d * ups_d;
    let angular_velocity = (rho_d * rho_d + ups_d * ups_d).sqrt();
    let angular_acceleration = rho_d * ups_d + (rho_dd * rho_dd + ups_dd * ups_dd).sqrt();

    // Theorem 2.
    let a_gains = &gains.attitude;
    let alpha_theta = T::one() + gains.hysteresis;
    let feedback_torque =
        (T::one() + alpha_theta * alpha_theta) * a_gains.mrp_saturation * lit(0.25)
            + a_gains.omega_saturation;
    let torque_max = feedforward_torque_bound(&inertia, angular_acceleration, angular_velocity)
        .add_scalar(feedback_torque);

    // Assumption 1 (the U* quantities).
    let margin = g - ka3;
    let s_rho_d = k.jerk / margin;
    let s_rho_dd = k.snap / margin + three * s_rho_d * s_rho_d;
    let s_l = margin / (ka12 * ka12 + margin * margin).sqrt();
    let s_ups_d = (s_rho_d + k.heading_rate) / s_l;
    let s_ups_dd = (s_rho_dd + k.heading_acceleration + two * s_rho_d * k.heading_rate) / s_l
        + three * s_ups_d * s_ups_d;
    let assumption = AssumptionBounds {
        thrust_direction_rate: s_rho_d,
        thrust_direction_acceleration: s_rho_dd,
        heading_projection_min: s_l,
        heading_axis_rate: s_ups_d,
        heading_axis_acceleration: s_ups_dd,
        angular_velocity: (s_rho_d * s_rho_d + s_ups_d * s_ups_d).sqrt(),
        angular_acceleration: s_rho_d * s_ups_d
            + (s_rho_dd * s_rho_dd + s_ups_dd * s_ups_dd).sqrt(),
    };
    let assumption_torque = feedforward_torque_bound(
        &inertia,
        assumption.angular_acceleration,
        assumption.angular_velocity,
    );

    let strict = |name, statement, lhs: T, rhs: T| Condition {
        name,
        statement,
        lhs,
        rhs,
        holds: lhs > rhs,
    };
    let tau = &limits.torque_max;
    let conditions = [
        strict(
            "assumption1.gravity_exceeds_vertical_acceleration",
            "g > K_a3 (eq:ThrustConditions)",
            g,
            ka3,
        ),
        strict(
            "assumption1.thrust_max",
            "T_max > m (g + sqrt(K_a12^2 + K_a3^2)) (eq:ThrustConditions)",
            limits.thrust_max,
            m * (g + (ka12 * ka12 + ka3 * ka3).sqrt()),
        ),
        strict(
            "assumption1.torque_max_roll",
            "tau_max_1 > J_11 U*_wd_dot + |J_22 - J_33| U*_wd^2 / 2 (eq:TorqueMaxCondition)",
            tau[0],
            assumption_torque[0],
        ),
        strict(
            "assumption1.torque_max_pitch",
            "tau_max_2 > J_22 U*_wd_dot + |J_33 - J_11| U*_wd^2 / 2 (eq:TorqueMaxCondition)",
            tau[1],
            assumption_torque[1],
        ),
        strict(
            "assumption1.torque_max_yaw",
            "tau_max_3 > J_33 U*_wd_dot + |J_11 - J_22| U*_wd^2 / 2 (eq:TorqueMaxCondition)",
            tau[2],
            assumption_torque[2],
        ),
        strict(
            "theorem1.saturation_margin",
            "g - K_a3 > M_p (Section IV, so that T_min > 0)",
            margin,
            mp,
        ),
        Condition {
            name: "theorem1.thrust_bound_within_actuator",
            statement: "T_max (actuator) >= m (sqrt(3) M_p + sqrt(K_a12^2 + (K_a3 + g)^2)) (eq:UpperBoundT)",
            lhs: limits.thrust_max,
            rhs: thrust_max,
            holds: limits.thrust_max >= thrust_max,
        },
        strict(
            "theorem2.torque_max_roll",
            "tau_max_1 > J_11 U_wd_dot + |J_22 - J_33| U_wd^2 / 2 + iota (eq:TorqueMaxConditionsTheorem)",
            tau[0],
            torque_max[0],
        ),
        strict(
            "theorem2.torque_max_pitch",
            "tau_max_2 > J_22 U_wd_dot + |J_33 - J_11| U_wd^2 / 2 + iota (eq:TorqueMaxConditionsTheorem)",
            tau[1],
            torque_max[1],
        ),
        strict(
            "theorem2.torque_max_yaw",
            "tau_max_3 > J_33 U_wd_dot + |J_11 - J_22| U_wd^2 / 2 + iota (eq:TorqueMaxConditionsTheorem)",
            tau[2],
            torque_max[2],
        ),
    ];
    Ok(Certificate {
        bounds: Bounds {
            thrust_min,
            thrust_max,
            filter_overshoot,
            u_rate,
            u_acceleration,
            thrust_direction_rate: rho_d,
            thrust_direction_acceleration: rho_dd,
            heading_projection_min,
            heading_axis_rate: ups_d,
            heading_axis_acceleration: ups_dd,
            angular_velocity,
            angular_acceleration,
            feedback_torque,
            torque_max,
            assumption,
        },
        conditions,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference::{ReferenceTrajectory, Trajectory};
    use approx::assert_relative_eq;

    fn paper() -> Certificate<f64> {
        certify(
            &Vehicle::paper(),
            &Limits::paper(),
            &Gains::paper(),
            &ReferenceTrajectory::paper_helix().constants(),
            FilterStart::Zero,
        )
        .unwrap()
    }

    /// Theorem 1 for Table I: the paper prints T ∈ [3.51, 6.19] N.
    #[test]
    fn theorem1_reproduces_the_paper() {
        let b = paper().bounds;
        assert_eq!((b.thrust_min * 100.0).round() / 100.0, 3.51);
        assert_eq!((b.thrust_max * 100.0).round() / 100.0, 6.19);
    }

    /// Independent recomputation of the Lemma 1 / Theorem 2 chain for the paper's set-up,
    /// written out step by step from the paper's formulas with the helix's constants.
    #[test]
    fn lemma1_and_theorem2_match_a_hand_evaluation() {
        use core::f64::consts::PI;
        let (m, g, mp, kf, ks) = (0.46f64, 9.81f64, 2.0f64, 2.0f64, 20.0f64);
        let f = 2.0 * PI / 15.0;
        let (ka12, ka3, kj, kss) = (
            f * f,
            f * f,
            f.powi(3) * 2f64.sqrt(),
            f.powi(4) * 2f64.sqrt(),
        );
        let (knd, kndd) = (PI * f, PI * PI * f * f);
        let tmin = m * (g - mp - ka3);
        let ul = (kf / ks).powf(kf / (ks - kf));
        let uud = 2.0 * 3f64.sqrt() * kf * ul * mp + kj;
        let uudd = 2.0 * 3f64.sqrt() * kf * mp * (kf * ul + ks) + kss;
        let urd = m * uud / tmin;
        let urdd = m * uudd / tmin + 3.0 * urd * urd;
        let lw = (tmin / m)
            / ((tmin / m).powi(2) + 2.0 * mp * mp + ka12 * ka12 + 2.0 * 2f64.sqrt() * mp * ka12)
                .sqrt();
        let uyd = (urd + knd) / lw;
        let uydd = (urdd + 2.0 * urd * knd + kndd) / lw + 3.0 * uyd * uyd;
        let uw = (urd * urd + uyd * uyd).sqrt();
        let uwd = urd * uyd + (urdd * urdd + uydd * uydd).sqrt();
        let iota = (1.0 + 1.02f64 * 1.02) * 0.206 / 4.0 + 0.045;
        let j = [2.24e-3, 2.9e-3, 5.3e-3];
        let b = paper().bounds;
        assert_relative_eq!(b.angular_velocity, uw, max_relative = 1e-12);
        assert_relative_eq!(b.angular_acceleration, uwd, max_relative = 1e-12);
        for i in 0..3 {
            let (jj, kk) = (j[(i + 1) % 3], j[(i + 2) % 3]);
            let t = j[i] * uwd + 0.5 * (jj - kk).abs() * uw * uw + iota;
            assert_relative_eq!(b.torque_max[i], t, max_relative = 1e-12);
        }
    }

    /// As written, Theorem 2's yaw condition fails for τ_max = 0.5 N m (see docs/paper-and-bounds.md), and the
    /// certificate says so with numbers rather than panicking.
    #[test]
    fn violations_are_reported_with_numbers() {
        let c = paper();
        let v = c.require_feasible().unwrap_err();
        assert_eq!(v.name, "theorem2.torque_max_yaw");
        assert_eq!(v.lhs, 0.5);
        assert!(v.rhs > 0.5);
        assert_eq!(c.violations().count(), 1);
        // Every Assumption 1 and Theorem 1 condition holds for the paper's set-up.
        assert!(c
            .conditions
            .iter()
            .filter(|c| !c.name.starts_with("theorem2"))
            .all(|c| c.holds));
    }

    #[test]
    fn equal_filter_gains_use_the_limit() {
        let mut g = Gains::<f64>::paper();
        g.position.ks = g.position.kf;
        let c = certify(
            &Vehicle::paper(),
            &Limits::paper(),
            &g,
            &TrajectoryConstants::zero(),
            FilterStart::Zero,
        )
        .unwrap();
        assert_relative_eq!(c.bounds.filter_overshoot, (-1f64).exp(), epsilon = 1e-12);
        // Continuity: a tiny difference gives nearly the same value.
        g.position.ks = g.position.kf * (1.0 + 1e-6);
        let c2 = certify(
            &Vehicle::paper(),
            &Limits::paper(),
            &g,
            &TrajectoryConstants::zero(),
            FilterStart::Zero,
        )
        .unwrap();
        assert_relative_eq!(c2.bounds.filter_overshoot, (-1f64).exp(), epsilon = 1e-6);
    }

    #[test]
    fn refuses_bad_parameters_with_names() {
        let mut g = Gains::<f64>::paper();
        g.position.saturation = 9.7;
        let k = ReferenceTrajectory::paper_helix().constants();
        let e = certify(
            &Vehicle::paper(),
            &Limits::paper(),
            &g,
            &k,
            FilterStart::Zero,
        )
        .unwrap_err();
        assert!(
            matches!(e, ParameterError::SaturationTooLarge { .. }),
            "{e:?}"
        );
        let mut v = Vehicle::<f64>::paper();
        v.mass = f64::NAN;
        let e = certify(&v, &Limits::paper(), &Gains::paper(), &k, FilterStart::Zero).unwrap_err();
        assert!(
            matches!(e, ParameterError::NotPositive { name: "mass", value } if value.is_nan()),
            "{e:?}"
        );
    }
}
