//! What a main run reports in `summary.json`: the a-priori bounds and conditions (the paper's,
//! the integral action's, the tight ones), what was observed against them, the final errors,
//! the path lifting's events and the settling times.

use controller_core::{Certificate, Gains, TrajectoryConstants};
use serde::Serialize;

use crate::bounds::certificate::TightReport;
use crate::model::rotor_plant::MixerCounts;
use crate::model::scenario::Precision;

/// A condition of the certificate, for `summary.json`.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct ConditionReport {
    /// Identifier.
    pub name: String,
    /// The inequality, with the paper's label.
    pub statement: String,
    /// Whether it holds.
    pub holds: bool,
    /// Left-hand side.
    pub lhs: f64,
    /// Right-hand side.
    pub rhs: f64,
}

/// The a-priori bounds (Theorems 1–2, Lemma 1).
#[derive(Clone, Debug, Serialize, PartialEq)]
#[allow(non_snake_case)]
pub struct APriori {
    /// `T_min` \[N\].
    pub thrust_min_N: f64,
    /// `T_max` of Theorem 1 \[N\].
    pub thrust_max_N: f64,
    /// Per-axis torque bound of Theorem 2 [N m].
    pub torque_max_Nm: [f64; 3],
    /// `U_ωd` [rad/s].
    pub angular_velocity_max_rad_s: f64,
    /// `U_ω̇d` [rad/s²].
    pub angular_acceleration_max_rad_s2: f64,
    /// `ι` [N m] (with tilt priority the largest of the per-axis levels).
    pub feedback_torque_max_Nm: f64,
    /// With `[gains.tilt_priority]` only: the per-axis feedback levels `ι_i` [N m], body axes
    /// (docs/tilt-priority.md; absent with the paper's radial feedback, whose level is the same
    /// on every axis).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub feedback_torque_axes_Nm: Option<[f64; 3]>,
    /// True when every condition holds.
    pub feasible: bool,
    /// Every condition with both sides.
    pub conditions: Vec<ConditionReport>,
    /// The tight bounds on the same quantities, beside these ([`crate::bounds::certificate`];
    /// with the integral action on, over the confining set its estimate widens).
    pub tight: TightReport,
    /// With the no-dive thrust (`[controller] thrust = "body-axis-projection"`) only: the
    /// a-priori interval `[T_floor, T_max]` \[N\] of the applied thrust, which replaces
    /// `[thrust_min_N, thrust_max_N]` in the bound check (absent with the paper's `T = m|u|`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub no_dive_thrust_interval_N: Option<[f64; 2]>,
    /// With `[gains.integral]` only: its gains and what it adds to the bounds (the bounds and
    /// conditions above are then the extended ones; docs/integral-action.md).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub integral: Option<IntegralReport>,
}

/// The integral action in `summary.json`: the gains as given and the certificate's terms.
#[derive(Clone, Debug, Serialize, PartialEq)]
#[allow(non_snake_case)]
pub struct IntegralReport {
    /// `k_i` [1/s³].
    pub k_i: f64,
    /// `M_i` [m/s²] per inertial axis.
    pub M_i_m_s2: [f64; 3],
    /// `R_i` [m/s³] per inertial axis.
    pub rate_m_s3: [f64; 3],
    /// `k_η` [1/s].
    pub k_eta: f64,
    /// The disturbance observer's gains (`null`: the integral of `z₁` alone).
    pub observer: Option<crate::model::scenario::ObserverConfig>,
    /// `L = M_p + M_i` [m/s²] per inertial axis.
    pub level_sum_m_s2: [f64; 3],
    /// `2 k_η |M_i|` [m/s³], added to `U_u̇`.
    pub u_rate_term_m_s3: f64,
    /// `k_η (2 k_η |M_i| + |R_i|)` [m/s⁴], added to `U_ü`.
    pub u_acceleration_term_m_s4: f64,
    /// `[a₀, …, a₅]` of the per-axis linearisation's characteristic polynomial, ascending
    /// (`a₅ = 0`: the quartic of the integral of `z₁` alone).
    pub characteristic_polynomial: [f64; 6],
    /// With `[gains.integral.feedforward_scale]` only: its gains, and the Assumption 1
    /// constants of the scaled feedforward every bound above is computed for.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub feedforward_scale: Option<FeedforwardScaleReport>,
}

/// The feedforward scale in `summary.json` (controller-core `feedforward_scale`).
#[derive(Clone, Debug, Serialize, PartialEq)]
#[allow(non_snake_case)]
pub struct FeedforwardScaleReport {
    /// The gains as given.
    pub gains: firmware::flight_tables::FeedforwardScaleTable,
    /// `[K_a12, K_a3]` [m/s²] of the scaled feedforward `(1 + μ_f) p̈_d`.
    pub acceleration_m_s2: [f64; 2],
    /// `K_j` [m/s³] of the scaled feedforward.
    pub jerk_m_s3: f64,
    /// `K_s` [m/s⁴] of the scaled feedforward.
    pub snap_m_s4: f64,
}

/// Extremes seen along the run (over the controller samples).
#[derive(Clone, Debug, Serialize, PartialEq)]
#[allow(non_snake_case)]
pub struct Observed {
    /// Smallest thrust command \[N\].
    pub thrust_min_N: f64,
    /// Largest thrust command \[N\].
    pub thrust_max_N: f64,
    /// Largest `|τ_i|` per axis [N m].
    pub torque_abs_max_Nm: [f64; 3],
    /// Largest `|ω_d|` [rad/s].
    pub angular_velocity_d_max_rad_s: f64,
    /// Largest `|ω̇_d|` [rad/s²].
    pub angular_acceleration_d_max_rad_s2: f64,
    /// Samples whose thrust or torque left the a-priori bounds.
    pub samples_outside_a_priori_bounds: u64,
    /// Samples whose torque, `|ω_d|` or `|ω̇_d|` exceeded the tight bounds.
    pub samples_above_tight_bounds: u64,
    /// Samples taken.
    pub samples: u64,
    /// Initial altitude minus the lowest altitude of the run \[m\] (over the samples; 0 if
    /// it never went below its start).
    pub altitude_loss_m: f64,
}

/// Errors at the last sample.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Final {
    /// Time of the last sample \[s\].
    pub time_s: f64,
    /// `|p − p_d|` \[m\].
    pub position_error_m: f64,
    /// `|ϑ̃|`.
    pub mrp_error: f64,
    /// `|ω̃|` [rad/s].
    pub angular_velocity_error_rad_s: f64,
}

/// Path-lifting jump counts.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct PathLiftingReport {
    /// Memory-quaternion resets.
    pub q_hat_resets: u32,
    /// MRP sign flips.
    pub m_flips: u32,
}

/// Settling times: the time after which an error stays below a threshold (`null` if never).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Settling {
    /// Position error below 1 mm from this time on \[s\].
    pub position_error_below_1mm_from_s: Option<f64>,
    /// MRP error below 1e-4 from this time on \[s\].
    pub mrp_error_below_1e_4_from_s: Option<f64>,
}

/// Everything `summary.json` holds.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Summary {
    /// Controller precision.
    pub precision: Precision,
    /// Bounds and conditions.
    pub a_priori: APriori,
    /// Observed extremes.
    pub observed: Observed,
    /// Errors at the end.
    #[serde(rename = "final")]
    pub final_: Final,
    /// Jump counts.
    pub path_lifting: PathLiftingReport,
    /// Settling times.
    pub settling: Settling,
    /// Rotor plant only (absent with the ideal plant): what the mixer gave up.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mixer: Option<MixerCounts>,
}

pub(super) fn a_priori(
    c: &Certificate<f64>,
    gains: &Gains<f64>,
    constants: &TrajectoryConstants<f64>,
    no_dive_thrust_interval: Option<[f64; 2]>,
    tight: TightReport,
) -> APriori {
    let b = &c.bounds;
    let integral = match (&gains.integral, &c.integral) {
        (Some(g), Some(i)) => Some(IntegralReport {
            k_i: g.gain,
            M_i_m_s2: g.level.into(),
            rate_m_s3: g.rate.into(),
            k_eta: g.bandwidth,
            observer: g.observer.map(|o| crate::model::scenario::ObserverConfig {
                velocity_gain_1_s: o.velocity_gain,
                disturbance_gain_1_s2: o.disturbance_gain,
                error_limit_m: o.error_limit,
            }),
            level_sum_m_s2: i.level_sum.into(),
            u_rate_term_m_s3: i.u_rate_term,
            u_acceleration_term_m_s4: i.u_acceleration_term,
            characteristic_polynomial: i.polynomial,
            feedforward_scale: g.feedforward_scale.map(|f| {
                let k = gains.law_constants(constants);
                FeedforwardScaleReport {
                    gains: firmware::flight_tables::FeedforwardScaleTable {
                        gain_1_s: f.gain,
                        excitation_m_s2: f.excitation,
                        level: f.level,
                        rate_1_s: f.rate,
                        tracking_limit_m: f.tracking_limit,
                    },
                    acceleration_m_s2: [k.horizontal_acceleration, k.vertical_acceleration],
                    jerk_m_s3: k.jerk,
                    snap_m_s4: k.snap,
                }
            }),
        }),
        _ => None,
    };
    APriori {
        thrust_min_N: b.thrust_min,
        thrust_max_N: b.thrust_max,
        torque_max_Nm: b.torque_max.into(),
        angular_velocity_max_rad_s: b.angular_velocity,
        angular_acceleration_max_rad_s2: b.angular_acceleration,
        feedback_torque_max_Nm: b.feedback_torque,
        feedback_torque_axes_Nm: c.tilt_priority.map(|_| b.feedback_torque_axes.into()),
        feasible: c.require_feasible().is_ok(),
        conditions: c
            .all_conditions()
            .map(|k| ConditionReport {
                name: k.name.into(),
                statement: k.statement.into(),
                holds: k.holds,
                lhs: k.lhs,
                rhs: k.rhs,
            })
            .collect(),
        tight,
        no_dive_thrust_interval_N: no_dive_thrust_interval,
        integral,
    }
}
