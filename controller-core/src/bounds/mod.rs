//! A-priori bounds and feasibility conditions: Assumption 1, Theorem 1, Lemma 1, Theorem 2.
//!
//! [`certify`] takes the vehicle, the actuator limits, the gains and the trajectory constants and
//! returns a [`Certificate`]: every bound the paper derives (thrust interval, bounds on `ω_d`,
//! `ω̇_d`, per-axis torque) and every condition with both sides of its inequality. The
//! conditions are sufficient, not necessary: a violated one means the theorems do not
//! guarantee the bounds for this set-up, not that a flight must fail.
//! [`Certificate::require_feasible`] turns the first violated condition into an error value.

use nalgebra::Vector3;

use crate::condition::strictly_less;
pub use crate::condition::{Condition, Violation};
use crate::desired_frame_bounds::{ChainBounds, DesiredFrameBounds};
use crate::gains::Gains;
use crate::heading_compensator::{yaw_bounds, CompensatorChain};
use crate::integral_stability::local_stability_conditions;
use crate::parameter_error::ParameterError;
use crate::position_saturation::PositionSaturation;
use crate::reference::TrajectoryConstants;
use crate::scalar::{lit, to_f64, Scalar};
use crate::torque_set::attitude_joint::JOINT_SLABS;
use crate::torque_set::{AttitudeJoint, TorqueSet};
use crate::vehicle::{Limits, Vehicle};

mod local;
pub use local::local_torque_set;
mod certificate;
mod vertical;
pub use certificate::{
    AssumptionBounds, Bounds, Certificate, FilterStart, IntegralCertificate, LocalCertificate,
    CONDITION_COUNT, LOCAL_CONDITION_COUNT,
};

/// Lemma 1's `U_l` (dimensionless) for the filter bandwidths `k_f`, `k_s` [1/s] and where the
/// filters start: `(k_f/k_s)^{k_f/(k_s−k_f)}` (`e⁻¹` if `k_f = k_s`) from rest, 1 from anywhere
/// in the set; `|u_s − u_f|` stays below `U_l` times the saturation set's width. No errors.
/// Source: Lemma 1.
pub fn overshoot<T: Scalar>(kf: T, ks: T, start: FilterStart) -> T {
    match start {
        FilterStart::InSaturationBox => T::one(),
        FilterStart::Zero => {
            let r = kf / ks;
            if (T::one() - r).abs() < lit(1e-9) {
                T::one() / T::one().exp()
            } else {
                (r * r.ln() / (T::one() - r)).exp()
            }
        }
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

/// The refusal when `M_p + M_i,z < g − K_a3` fails (extended Theorem 1: `T_min` would not be
/// positive); `total = M_p + M_i,z`, `limit = g − K_a3` [m/s²].
pub(crate) fn integral_margin_error<T: Scalar>(total: T, limit: T) -> ParameterError {
    ParameterError::OutOfRange {
        name: "M_p + M_i_z (must be < g - K_a3)",
        value: to_f64(total),
        low: 0.0,
        high: to_f64(limit),
    }
}

/// Computes every bound and condition of the paper for this set-up.
///
/// Inputs: vehicle (`m` \[kg\], `J` [kg m²], `g` [m/s²]), limits (`T_max` \[N\], `τ_max` [N m]),
/// gains (Table I), trajectory constants (Assumption 1) and where the filters start.
/// Errors: [`ParameterError`] if an input is not positive and finite or `M_p ≥ g − K_a3` makes
/// `T_min ≤ 0` (every later bound divides by it); with the integral action, `M_p + M_i,z ≥
/// g − K_a3` is refused likewise ([`ParameterError::OutOfRange`] naming `"M_p + M_i_z"`).
/// With the integral action the bounds are the extended ones ([`Bounds`],
/// [`IntegralCertificate`]; extension, docs/integral-action.md); without it every number is the
/// paper's; with its feedforward scale every bound is computed for the constants of the scaled
/// feedforward ([`Gains::law_constants`]). A violated *feasibility* condition is not an
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
    let mut certificate =
        certify_without_joint_bound(vehicle, limits, gains, constants, filter_start)?;
    // Tilt priority's attitude terms bounded together where that is tighter (docs/torque-set.md,
    // "The attitude terms bounded together"); the same grid on the board.
    if let Some(t) = &gains.tilt_priority {
        certificate.bounds.torque_set.attitude_joint = AttitudeJoint::of(
            t,
            gains.attitude.mrp_saturation,
            gains.attitude.k_mrp,
            gains.hysteresis,
            JOINT_SLABS,
        );
    }
    Ok(certificate)
}

/// [`certify`] with the torque set's attitude terms charged apart only (its
/// [`TorqueSet::attitude_joint`] is `None`): every other number is the same, at a fraction of
/// the cost with tilt priority, for callers that read no support of the set (the thrust bounds,
/// the per-axis bounds, the conditions). Errors: as [`certify`].
/// Source: as [`certify`].
pub fn certify_without_joint_bound<T: Scalar>(
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
    let requested = constants;
    // The reference as the law applies it (the feedforward scale widens its constants).
    let constants = &gains.law_constants(constants);
    let (m, g, inertia) = (vehicle.mass, vehicle.gravity, vehicle.inertia);
    let p = &gains.position;
    let (mp, kf, ks) = (p.saturation, p.kf, p.ks);
    // The integral action's local stability is the regime's that persists: the local one with
    // the envelope design (docs/envelope-design.md).
    let settled = gains.local.map_or(*p, |l| l.position(p));
    let k = constants;
    let (ka12, ka3) = (k.horizontal_acceleration, k.vertical_acceleration);
    // The downward level: `M_p`, or `M_down` with the vertical channel apart.
    let down = p.downward_level();
    if !strictly_less(down, g - ka3) {
        return Err(ParameterError::SaturationTooLarge {
            saturation: to_f64(down),
            limit: to_f64(g - ka3),
        });
    }
    let level_sum = gains.integral.map(|i| {
        let mut l = i.level.add_scalar(mp);
        l.z = i.level.z + down;
        l
    });
    if let Some(l) = &level_sum {
        if !strictly_less(l.z, g - ka3) {
            return Err(integral_margin_error(l.z, g - ka3));
        }
    }
    let two = lit::<T>(2.0);

    // Theorem 1. `T_min` needs only the vertical level (`M_p`, plus `M_i,z` with the integral
    // action). `T_max`: `|u| ≤ sup|u_f| + |g e₃ + p̈_d (+ η_f)|`, where `u_f` is a convex
    // combination of values of ubar_p, so `sup|u_f| = reach M_p`: √3 M_p for the paper's cube,
    // M_p for the norm shape's ball (docs/position-saturation.md). With the integral action and
    // the paper's shape the extended bound keeps the horizontal and vertical parts of
    // `u_f + η_f` apart instead (docs/integral-action.md).
    let norm_shape = p.saturation_shape == PositionSaturation::Norm;
    let reach = p.saturation_shape.norm_factor::<T>();
    // The estimate's box (zero without the integral action).
    let estimate = gains.integral.map_or(Vector3::zeros(), |i| i.level);
    let thrust_min = match &level_sum {
        None => m * (g - mp - ka3),
        Some(l) => m * (g - ka3 - l.z),
    };
    let thrust_max = match &level_sum {
        Some(l) if !norm_shape => {
            let horizontal = (l.x * l.x + l.y * l.y).sqrt() + ka12;
            let vertical = g + ka3 + l.z;
            m * (horizontal * horizontal + vertical * vertical).sqrt()
        }
        _ => {
            let horizontal = estimate.xy().norm() + ka12;
            let vertical = g + ka3 + estimate.z;
            m * (reach * mp + (horizontal * horizontal + vertical * vertical).sqrt())
        }
    };

    // Lemma 1.
    let filter_overshoot = overshoot(kf, ks, filter_start);
    let mut u_rate = two * reach * kf * filter_overshoot * mp + k.jerk;
    let mut u_acceleration = two * reach * kf * mp * (kf * filter_overshoot + ks) + k.snap;
    // |η̇_f| and |η̈_f| over the states reachable from arming (crate::integral's reachable-set
    // bound, never above the whole box's 2 k_η M_i and k_η (2 k_η M_i + R_i)).
    let integral_terms = gains.integral.map(|i| {
        (
            i.filtered_rate_bound().norm(),
            i.filtered_acceleration_bound().norm(),
        )
    });
    if let Some((rate_term, acceleration_term)) = integral_terms {
        u_rate += rate_term;
        u_acceleration += acceleration_term;
    }
    // The quadratic terms of Lemma 1's chain: the paper's 3, or the tangential form's
    // (crate::lemma1_form); the paper's form gives its numbers bit for bit.
    let quadratic = gains.lemma1.coefficients::<T>();
    let rho_d = m * u_rate / thrust_min;
    let rho_dd = m * u_acceleration / thrust_min + quadratic.whole * rho_d * rho_d;
    let rho_dd_projected = m * u_acceleration / thrust_min + quadratic.projected * rho_d * rho_d;
    let a = thrust_min / m;
    // `|u_xy|² − K_a12²` at most: the paper's `2M_p² + 2√2 M_p K_a12` for the cube; otherwise
    // from the largest horizontal feedback `l_xy`: `|L_xy|` (the extended bound) or
    // `M_p + |M_i,xy|` (the norm shape's ball plus the estimate's box).
    let horizontal_feedback = match &level_sum {
        None if !norm_shape => None,
        Some(l) if !norm_shape => Some((l.x * l.x + l.y * l.y).sqrt()),
        _ => Some(mp + estimate.xy().norm()),
    };
    let lateral = match horizontal_feedback {
        None => two * mp * mp + ka12 * ka12 + two * two.sqrt() * mp * ka12,
        Some(lxy) => lxy * lxy + ka12 * ka12 + two * lxy * ka12,
    };
    let heading_projection_min = a / (a * a + lateral).sqrt();
    // With the vertical channel apart, the horizontal and vertical parts of `u` are bounded apart
    // and a vertical change of `u` turns `ρ` only through the tilt (docs/vertical-channel.md):
    // that chain replaces the one above, which stays bit for bit without the vertical channel.
    let chain = p.vertical.map(|v| {
        let overshoots = (filter_overshoot, overshoot(v.kf, v.ks, filter_start));
        vertical::vertical_chain((m, g), p, &v, k, gains.integral.as_ref(), overshoots)
    });
    let thrust_min = chain.map_or(thrust_min, |c| c.thrust_min);
    let thrust_max = chain.map_or(thrust_max, |c| c.thrust_max);
    let u_rate = chain.map_or(u_rate, |c| c.u_rate);
    let u_acceleration = chain.map_or(u_acceleration, |c| c.u_acceleration);
    let rho_d = chain.map_or(rho_d, |c| c.rho_d);
    let rho_dd = chain.map_or(rho_dd, |c| c.rho_dd);
    let rho_dd_projected = chain.map_or(rho_dd_projected, |c| c.rho_dd_projected);
    let heading_projection_min = chain.map_or(heading_projection_min, |c| c.heading_projection_min);
    let ups_d = (rho_d + k.heading_rate) / heading_projection_min;
    // `ω̇_d` reads `ϋ` only across `υ`, where the radial part of `ρ̈` drops out of `ϖ̈`
    // (crate::lemma1_form), so the paper's form takes the projected bound too: it is `U_ρ̈`.
    let ups_dd = (rho_dd_projected + two * rho_d * k.heading_rate + k.heading_acceleration)
        / heading_projection_min
        + quadratic.projected * ups_d * ups_d;
    let angular_velocity = (rho_d * rho_d + ups_d * ups_d).sqrt();
    let angular_acceleration =
        rho_d * ups_d + (rho_dd_projected * rho_dd_projected + ups_dd * ups_dd).sqrt();

    // Theorem 2.
    let a_gains = &gains.attitude;
    let alpha_theta = T::one() + gains.hysteresis;
    // The radial MRP term's bound `(1 + (1 + δ)²) M_ϑ/4`.
    let radial_mrp = (T::one() + alpha_theta * alpha_theta) * a_gains.mrp_saturation * lit(0.25);
    let feedback_torque_axes = match &gains.tilt_priority {
        None => Vector3::repeat(radial_mrp + a_gains.omega_saturation),
        Some(t) => t.feedback_levels(a_gains.mrp_saturation, gains.hysteresis),
    };
    let feedback_torque = feedback_torque_axes.max();
    let chain_bounds = ChainBounds {
        thrust_direction_rate: rho_d,
        thrust_direction_acceleration_across: rho_dd_projected,
        heading_projection_min,
        heading_rate: k.heading_rate,
        heading_acceleration: k.heading_acceleration,
        angular_velocity,
        angular_acceleration,
    };
    // With the compensated heading the desired frame is built from the compensator's heading,
    // not the reference's: Lemma 1's norms above bound the reference's frame, so the norms are
    // the compensated frame's components' (crate::heading_compensator) from here on.
    let (desired_frame, angular_velocity, angular_acceleration) = match &gains.heading_compensator {
        None => (
            DesiredFrameBounds::new(&chain_bounds, &inertia),
            angular_velocity,
            angular_acceleration,
        ),
        Some(hc) => {
            let yaw = yaw_bounds(
                hc,
                &CompensatorChain {
                    thrust_direction_rate: rho_d,
                    horizontal_share: (T::one() - heading_projection_min * heading_projection_min)
                        .max(T::zero())
                        .sqrt(),
                    heading_projection_min,
                    heading_rate: k.heading_rate,
                    heading_acceleration: k.heading_acceleration,
                },
            );
            let frame = DesiredFrameBounds::compensated(&chain_bounds, yaw, &inertia);
            let hypot = |a: T, b: T| (a * a + b * b).sqrt();
            (
                frame,
                hypot(frame.tilt_rate, frame.yaw_rate),
                hypot(frame.tilt_acceleration, frame.yaw_acceleration),
            )
        }
    };

    let set_rates = desired_frame.norm_bounds((angular_velocity, angular_acceleration));
    // Theorem 2's per-axis bounds: Lemma 1's norms as the paper writes them, or with the desired
    // frame's form the set's norms below (a rotation keeps norms, so any bound on them serves;
    // the bound along each axis is then the set's extent, docs/torque-set.md).
    let per_axis_rates = if gains.lemma1.per_axis_from_desired_frame() {
        set_rates
    } else {
        (angular_velocity, angular_acceleration)
    };
    let torque_max = feedforward_torque_bound(&inertia, per_axis_rates.1, per_axis_rates.0)
        + feedback_torque_axes;
    // The set's feedforward takes the norms of `ω_d`, `ω̇_d` from their desired-frame
    // components where that is tighter than Lemma 1's chain (Theorem 2's conditions above keep
    // the chain's norms unless the form is the desired frame's). The feedback's shapes: one ball
    // for the paper's law; with tilt priority the MRP term's ball, the trace term's ball and
    // disks and the damping's box.
    let torque_set = match &gains.tilt_priority {
        None => TorqueSet::new(
            inertia,
            set_rates.0,
            set_rates.1,
            radial_mrp + a_gains.omega_saturation,
            feedback_torque_axes,
        ),
        Some(t) => TorqueSet::tilt_priority(
            inertia,
            set_rates.0,
            set_rates.1,
            radial_mrp,
            t.trace_weights,
            // The turn-over term's per-axis bounds widen the damping's box (docs/turn-over.md).
            t.omega_levels + t.turn_over_bounds(gains.hysteresis),
        ),
    };

    // Assumption 1 (the U* quantities).
    let margin = g - ka3;
    let s_rho_d = k.jerk / margin;
    let s_rho_dd = k.snap / margin + quadratic.whole * s_rho_d * s_rho_d;
    let s_rho_dd_projected = k.snap / margin + quadratic.projected * s_rho_d * s_rho_d;
    let s_l = margin / (ka12 * ka12 + margin * margin).sqrt();
    let s_ups_d = (s_rho_d + k.heading_rate) / s_l;
    let s_ups_dd = (s_rho_dd_projected + k.heading_acceleration + two * s_rho_d * k.heading_rate)
        / s_l
        + quadratic.projected * s_ups_d * s_ups_d;
    let assumption = AssumptionBounds {
        thrust_direction_rate: s_rho_d,
        thrust_direction_acceleration: s_rho_dd,
        heading_projection_min: s_l,
        heading_axis_rate: s_ups_d,
        heading_axis_acceleration: s_ups_dd,
        angular_velocity: (s_rho_d * s_rho_d + s_ups_d * s_ups_d).sqrt(),
        angular_acceleration: s_rho_d * s_ups_d
            + (s_rho_dd_projected * s_rho_dd_projected + s_ups_dd * s_ups_dd).sqrt(),
    };
    let assumption_torque = feedforward_torque_bound(
        &inertia,
        assumption.angular_acceleration,
        assumption.angular_velocity,
    );

    let strict = Condition::strict;
    let theorem2_statement = |paper: &'static str, desired_frame: &'static str| {
        if gains.lemma1.per_axis_from_desired_frame() {
            desired_frame
        } else {
            paper
        }
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
        match (&level_sum, &p.vertical) {
            (None, None) => strict(
                "theorem1.saturation_margin",
                "g - K_a3 > M_p (Section IV, so that T_min > 0)",
                margin,
                mp,
            ),
            (None, Some(_)) => strict(
                "theorem1.saturation_margin",
                "g - K_a3 > M_down (vertical channel apart, docs/vertical-channel.md)",
                margin,
                down,
            ),
            (Some(l), _) => strict(
                "theorem1.saturation_margin",
                "g - K_a3 > M_p + M_i,z (extended Theorem 1, docs/integral-action.md)",
                margin,
                l.z,
            ),
        },
        Condition {
            name: "theorem1.thrust_bound_within_actuator",
            statement: match (&level_sum, norm_shape) {
                _ if p.vertical.is_some() => "T_max (actuator) >= m sqrt((H + |M_i,xy| + K_a12)^2 + (g + K_a3 + M_i,z + M_up)^2), H the horizontal reach of ubar_p (vertical channel apart, docs/vertical-channel.md)",
                (None, false) => "T_max (actuator) >= m (sqrt(3) M_p + sqrt(K_a12^2 + (K_a3 + g)^2)) (eq:UpperBoundT)",
                (None, true) => "T_max (actuator) >= m (M_p + sqrt(K_a12^2 + (K_a3 + g)^2)) (eq:UpperBoundT, norm-saturated ubar_p: docs/position-saturation.md)",
                (Some(_), false) => "T_max (actuator) >= m sqrt((|L_xy| + K_a12)^2 + (g + K_a3 + L_z)^2), L = M_p + M_i (extended Theorem 1, docs/integral-action.md)",
                (Some(_), true) => "T_max (actuator) >= m (M_p + sqrt((|M_i,xy| + K_a12)^2 + (g + K_a3 + M_i,z)^2)) (extended Theorem 1, norm-saturated ubar_p: docs/position-saturation.md)",
            },
            lhs: limits.thrust_max,
            rhs: thrust_max,
            holds: limits.thrust_max >= thrust_max,
        },
        strict(
            "theorem2.torque_max_roll",
            theorem2_statement(
                "tau_max_1 > J_11 U_wd_dot + |J_22 - J_33| U_wd^2 / 2 + iota (eq:TorqueMaxConditionsTheorem)",
                "tau_max_1 > J_11 U_wd_dot + |J_22 - J_33| U_wd^2 / 2 + iota, U the desired frame's norms (eq:TorqueMaxConditionsTheorem; docs/torque-set.md)",
            ),
            tau[0],
            torque_max[0],
        ),
        strict(
            "theorem2.torque_max_pitch",
            theorem2_statement(
                "tau_max_2 > J_22 U_wd_dot + |J_33 - J_11| U_wd^2 / 2 + iota (eq:TorqueMaxConditionsTheorem)",
                "tau_max_2 > J_22 U_wd_dot + |J_33 - J_11| U_wd^2 / 2 + iota, U the desired frame's norms (eq:TorqueMaxConditionsTheorem; docs/torque-set.md)",
            ),
            tau[1],
            torque_max[1],
        ),
        strict(
            "theorem2.torque_max_yaw",
            theorem2_statement(
                "tau_max_3 > J_33 U_wd_dot + |J_11 - J_22| U_wd^2 / 2 + iota (eq:TorqueMaxConditionsTheorem)",
                "tau_max_3 > J_33 U_wd_dot + |J_11 - J_22| U_wd^2 / 2 + iota, U the desired frame's norms (eq:TorqueMaxConditionsTheorem; docs/torque-set.md)",
            ),
            tau[2],
            torque_max[2],
        ),
    ];
    let mut certificate = Certificate {
        bounds: Bounds {
            thrust_min,
            thrust_max,
            filter_overshoot,
            u_rate,
            u_acceleration,
            thrust_direction_rate: rho_d,
            thrust_direction_acceleration: rho_dd,
            thrust_direction_acceleration_projected: rho_dd_projected,
            heading_projection_min,
            heading_axis_rate: ups_d,
            heading_axis_acceleration: ups_dd,
            angular_velocity,
            angular_acceleration,
            feedback_torque,
            feedback_torque_axes,
            torque_max,
            torque_set,
            assumption,
            desired_frame,
            aligned_feedforward: desired_frame.aligned_feedforward(&inertia),
        },
        conditions,
        integral: match (gains.integral, level_sum, integral_terms) {
            (Some(i), Some(l), Some((rate_term, acceleration_term))) => Some(IntegralCertificate {
                level_sum: l,
                u_rate_term: rate_term,
                u_acceleration_term: acceleration_term,
                polynomial: crate::integral_stability::characteristic_polynomial(&settled, &i),
                conditions: local_stability_conditions(&settled, &i),
            }),
            _ => None,
        },
        local: match &gains.local {
            Some(l) => Some(local::local_certificate(
                vehicle, limits, gains, l, requested,
            )?),
            None => None,
        },
        tilt_priority: gains.tilt_priority.map(|t| {
            let (lhs, rhs) = t.hysteresis_band(a_gains, gains.hysteresis);
            [strict(
                "tilt_priority.hysteresis_band",
                "M_theta k_theta / sqrt(M_theta^2 + k_theta^2) > (tr G - min g)((1+delta)^2 - 1)(1+delta) (docs/tilt-priority.md)",
                lhs,
                rhs,
            )]
        }),
    };
    if let Some(l) = &certificate.local {
        // Every thrust the law asks for: the hull of the two regimes' Theorem 1 intervals.
        let b = &mut certificate.bounds;
        b.thrust_min = b.thrust_min.min(l.bounds.thrust_min);
        b.thrust_max = b.thrust_max.max(l.bounds.thrust_max);
    }
    Ok(certificate)
}

#[cfg(test)]
mod tests;

#[cfg(test)]
mod integral_tests;

#[cfg(test)]
mod norm_shape_tests;
