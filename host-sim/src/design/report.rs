//! The files of a design: `design.json`, `design.md` (with plots), `scenario.toml` (runs as is
//! with `host-sim --scenario`) and `firmware.toml` (the flight file the firmware build takes).

use serde::Serialize;

use super::evaluate::{
    Trial, ALTITUDE_WEIGHT_S_PER_M, DISTURBANCE_LOSS_WEIGHT_S_PER_M, DOUBLED_LAG_WEIGHT,
    NOMINAL_TASK_WEIGHT, RANDOM_STARTS, RANDOM_STARTS_MARGIN_S, RANDOM_STARTS_SEED,
    TAIL_ATTITUDE_DEG, TAIL_S, TURNED_START_ANGLES_DEG, UNSETTLED_TASK_S,
};
use super::flight::{gains_config, limits_config};
use super::options::{DesignOptions, Scored};
use super::reference::Reference;
use super::variables::Choices;
use super::vehicle::DesignVehicle;
use crate::model::scenario::{GainsConfig, LimitsConfig, TrajectoryConfig};
use crate::studies::compare::SanityRow;

/// One condition of the certificate.
#[derive(Clone, Debug, Serialize)]
pub struct ConditionEntry {
    /// Identifier.
    pub name: String,
    /// The inequality with the paper's label.
    pub statement: String,
    /// Whether it holds.
    pub holds: bool,
    /// Left-hand side.
    pub lhs: f64,
    /// Right-hand side.
    pub rhs: f64,
    /// `lhs − rhs` (positive when it holds).
    pub slack: f64,
    /// Certified with the tight bounds, Theorem 2's torque conditions: the paper's bound (the
    /// `rhs` above is the tight one) and whether the condition holds with it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub paper: Option<(f64, bool)>,
}

/// `certificate`.
#[derive(Clone, Debug, Serialize)]
pub struct CertificateEntry {
    /// The bounds Theorem 2's torque conditions and the rotor fit are judged with.
    pub bounds: super::tight::BoundsKind,
    /// The chain Lemma 1's `U_ω̇d` comes from: `"paper"`, `"tangential"`
    /// (docs/tangential-lemma1.md) or `"desired_frame"` (the tangential chain, Theorem 2's
    /// per-axis conditions on the desired frame's norms, docs/torque-set.md); the flight file
    /// carries the same.
    pub lemma1: &'static str,
    /// Every condition holds.
    pub all_hold: bool,
    /// Every condition holds and the certified set fits with the margin with the paper's bounds too: what
    /// the firmware's gate re-checks on board (a flight file is written only then).
    pub paper_certified: bool,
    /// Every condition, in the paper's order (from `controller_core::bounds::certify`).
    pub conditions: Vec<ConditionEntry>,
}

/// The rotor fit of the certified `(T, τ)` set (`firmware::mixer::Mixer::set_margin`), and the
/// per-axis report of the box of its bounds (`Mixer::box_fit`).
#[derive(Clone, Debug, Serialize)]
#[allow(non_snake_case)]
pub struct RotorFitEntry {
    /// The shape of the certified torque set: `"set"` (Theorem 2's terms,
    /// `controller_core::TorqueSet`; with the tight bounds too, which take its shape with their
    /// norms, where they once certified the box of their per-axis bounds).
    pub shape: &'static str,
    /// The certified set fits the rotor range.
    pub fits: bool,
    /// It fits the range shrunk by the requested margin at both ends.
    pub fits_with_margin: bool,
    /// Smallest headroom of the set over the rotors, fraction of the rotor range.
    pub margin: f64,
    /// The requested margin.
    pub requested_margin: f64,
    /// The box of the per-axis bounds fits too (every corner at once; not required).
    pub box_fits: bool,
    /// Certified thrust interval \[N\].
    pub thrust_needed_N: [f32; 2],
    /// Thrust interval the rotors realise with every torque at its per-axis bound at once \[N\]
    /// (the box's; informative).
    pub thrust_capacity_N: [f32; 2],
    /// Certified per-axis torque bounds [N m].
    pub torque_needed_Nm: [f32; 3],
    /// Per-axis torque capacity over the certified thrust interval [N m]: the `τ_max` limits
    /// (each axis alone).
    pub torque_capacity_Nm: [f32; 3],
    /// How the set was fitted (`--airmode`): `set` (the thrust interval times the torque set)
    /// or `airmode` (every torque at some thrust: `margin` is then the shadow fit's headroom,
    /// docs/airmode.md).
    pub fit: super::authority::RotorFit,
    /// With airmode: the headroom of the feedforward at zero attitude error over Theorem 1's
    /// interval (the aligned fit), fraction of the rotor range; `null` without airmode.
    pub aligned_margin: Option<f64>,
    /// With airmode: the aligned fit leaves the requested margin, so airmode's convergence
    /// argument is a proof (docs/airmode.md); `false`: shown by simulation only. `null` without.
    pub airmode_convergence_proven: Option<bool>,
}

/// `local_regime`: the envelope design's local regime (docs/envelope-design.md); its gains are
/// `gains.local`.
#[derive(Clone, Debug, Serialize)]
#[allow(non_snake_case)]
pub struct LocalRegimeEntry {
    /// Largest attitude error angle inside `{E ≤ E_out}` \[deg\].
    pub angle_out_deg: f64,
    /// Largest `|ω̃_i|` inside `{E ≤ E_out}` [rad/s], body axes.
    pub omega_error_out_rad_s: [f64; 3],
    /// `U_ω̇d` of the local gains' Lemma 1 [rad/s²].
    pub angular_acceleration_bound_rad_s2: f64,
    /// Per-axis extent of the local torque set [N m].
    pub torque_extent_Nm: [f64; 3],
}

/// `reference`.
#[derive(Clone, Debug, Serialize)]
pub struct ReferenceEntry {
    /// The requested `[trajectory]`.
    pub requested: TrajectoryConfig,
    /// The `[trajectory]` the design is certified for.
    pub certified: TrajectoryConfig,
    /// The requested reference could not be certified and was slowed down.
    pub scaled: bool,
    /// Time scale applied (frequencies times this).
    pub scale: f64,
    /// Why the requested reference could not be certified (binding condition with numbers).
    pub binding: Option<String>,
    /// Set when the certified reference is the requested path with the heading held at
    /// `ψ_d(0)` (`design`'s first fallback): why the requested heading was set aside. Absent
    /// otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub heading_held: Option<String>,
}

/// `objective`.
#[derive(Clone, Debug, Serialize)]
pub struct ObjectiveEntry {
    /// The objective in words.
    pub definition: String,
    /// Its value (lower is better).
    pub value: f64,
    /// Altitude lost recovering from upside down at hover \[m\].
    pub altitude_loss_upside_down_m: f64,
    /// Where that altitude went: the turn-over (time, loss and sink rate when the body z axis
    /// came back above the horizon); the rest is the braking after it.
    pub upside_down_turn_over: Option<super::turn_over::TurnOver>,
    /// Worst settling time over the seven 180° starts \[s\].
    pub worst_settling_180_s: Option<f64>,
    /// Settling time per 180° start \[s\].
    pub settling_180_s: Vec<(String, Option<f64>)>,
    /// With the integral action (the default; absent with `--no-integral`): the disturbed hover (plant mass `× (1 + e)`, force `f` of its weight
    /// down, from rest; `design::evaluate::disturbed_hover`): settling time \[s\] (`null`: not
    /// settled) and the altitude lost \[m\]. `null` without the integral action.
    pub disturbed_hover: Option<DisturbedEntry>,
    /// The nominal tasks (hover, 1 m step, 30° roll, 10 s each, as `compare` flies them): the
    /// design's row first, then the baselines' (Lee et al., the PX4-style cascade) on the same
    /// vehicle, plant and motor lag.
    pub nominal_tasks: Vec<SanityRow>,
    /// Every constraint met (all runs converge, nominal and doubled motor lag, and the disturbed
    /// hover with the integral action).
    pub constraints_met: bool,
    /// The certified authority in flight terms: `[T_min, T_max] / (m g)` and the feedback
    /// angular acceleration `ι / J_ii` [rad/s²] per axis.
    pub authority: AuthorityEntry,
}

/// `objective.disturbed_hover`.
#[derive(Clone, Debug, Serialize)]
pub struct DisturbedEntry {
    /// Settling time (5 cm, 2°, until the end) \[s\]; `None`: not settled.
    pub settling_s: Option<f64>,
    /// `z(0) − min z` \[m\].
    pub altitude_loss_m: f64,
    /// `|p − p_d|` at the end \[m\].
    pub final_position_error_m: f64,
}

/// The certified authority in flight terms.
#[derive(Clone, Debug, Serialize)]
pub struct AuthorityEntry {
    /// `[T_min, T_max]` of Theorem 1 over the weight `m g`.
    pub thrust_interval_over_weight: [f64; 2],
    /// `ι / J_ii` [rad/s²]: the angular acceleration the saturated feedback can command.
    pub feedback_angular_acceleration_rad_s2: [f64; 3],
}

/// `margins`.
#[derive(Clone, Debug, Serialize)]
pub struct MarginsEntry {
    /// Rotor-fit margin of the certified set (fraction of the rotor range).
    pub rotor_fit: f64,
    /// Smallest relative slack over the conditions, `(lhs − rhs)/|rhs|`, and its condition.
    pub tightest_condition: (String, f64),
    /// The vehicle's motor time constant \[s\].
    pub motor_time_constant_s: f64,
    /// Largest motor time constant with which the seven 180° starts still converge \[s\].
    pub motor_time_constant_max_converging_s: Option<f64>,
    /// All seven 180° starts, the turned starts ([`super::evaluate::turned_starts`]) and the
    /// random starts ([`super::evaluate::random_starts`]) converge with the motor time constant
    /// doubled (no limit cycle).
    pub doubled_lag_converges: bool,
    /// Settling per 180° start with the motor time constant doubled \[s\].
    pub doubled_lag_settling_180_s: Vec<(String, Option<f64>)>,
}

/// `heading_search`: one searched heading's outcome, after its fallbacks.
#[derive(Clone, Debug, Serialize)]
pub struct HeadingCandidate {
    /// Whether it flies the compensated heading (docs/heading-compensator.md); `false`: the
    /// paper's desired frame.
    pub compensated: bool,
    /// Its best design's objective as compared, before the local position loop's polish,
    /// which only the design kept gets (lower is better; graded penalty when unconverged).
    pub objective: f64,
    /// Whether that design met the convergence constraints.
    pub constraints_met: bool,
    /// Whether it was designed on the long-run fallback's runs.
    pub long_runs: bool,
}

/// `law_search`: one searched attitude law's outcome.
#[derive(Clone, Debug, Serialize)]
pub struct LawCandidate {
    /// The law.
    pub law: super::variables::AttitudeLaw,
    /// Its best design's objective as compared, before the local position loop's polish,
    /// which only the design kept gets (lower is better; graded penalty when unconverged).
    pub objective: f64,
    /// Its best design met the convergence constraints.
    pub constraints_met: bool,
}

/// `design.json`.
#[derive(Clone, Debug, Serialize)]
#[allow(non_snake_case)]
pub struct Report {
    /// Vehicle name.
    pub vehicle: String,
    /// Vehicle source.
    pub vehicle_source: String,
    /// Vehicle file.
    pub vehicle_file: String,
    /// Optimiser seed.
    pub seed: u64,
    /// Length of the scoring runs and of the written scenario \[s\] (`--duration-s`).
    pub duration_s: f64,
    /// Evaluations spent.
    pub evaluations: usize,
    /// Wall time of the design \[s\] (with the fallback, both attempts).
    pub wall_time_s: f64,
    /// Set when this design is `design`'s fallback (the velocity-limited feedback on longer
    /// runs, [`super::options::Fallback`]): why the first attempt was set aside; `null` otherwise.
    pub fallback: Option<String>,
    /// The certificate.
    pub certificate: CertificateEntry,
    /// The rotor fit of the certified set.
    pub rotor_fit: RotorFitEntry,
    /// The envelope design's local regime (`--envelope`), `null` when the design has none.
    pub local_regime: Option<LocalRegimeEntry>,
    /// The local regime refined after the search (`crate::design::refine`): the objectives
    /// before and after, and whether the refined one is this design's; `null` without the
    /// envelope design or without the compensated heading.
    pub local_refinement: Option<super::refine::Refinement>,
    /// Tilt priority's turn-over term refined after the search
    /// (`crate::design::refine::turn_over`, docs/turn-over.md): the objectives before and
    /// after, and whether the refined design is this one; `null` with the paper's law.
    pub turn_over_refinement: Option<super::refine::Refinement>,
    /// The local position loop's frequency and damping polished last on a grid
    /// (`crate::design::refine::local_loop`, docs/envelope-design.md): the objectives before and
    /// after, and whether the polished loop is this design's; `null` without a local regime.
    pub local_loop_refinement: Option<super::refine::Refinement>,
    /// The local regime's agility refined last ([`super::refine::local_agility`]), when it ran.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub local_agility_refinement: Option<super::refine::Refinement>,
    /// Gains (scenario `[gains]`).
    pub gains: GainsConfig,
    /// Limits (scenario `[limits]`): what the rotors deliver.
    pub limits: LimitsConfig,
    /// The attitude feedback of this design (`paper` or `tilt-priority`).
    pub law: super::variables::AttitudeLaw,
    /// Every law searched (`--law`, both by default) with its best design's objective and
    /// whether it met the convergence constraints; this design's law is the better one.
    pub law_search: Vec<LawCandidate>,
    /// With `--heading both` (the default): each heading's design, the written one the first
    /// that meets the convergence constraints on the shorter runs with the lower objective;
    /// empty when one heading was asked for.
    pub heading_search: Vec<HeadingCandidate>,
    /// With the integral action (the default; absent with `--no-integral`): the disturbance the bounded integral action covers and its level
    /// `M_i` [m/s²] (its gains are in `gains.integral`); `null` without.
    pub integral: Option<super::integral::IntegralSpec>,
    /// The thrust flown and written (`--thrust`): its mode, vertical priority's floor and the
    /// certified thrust interval `[T_lo, T_hi]` \[N\] of the set `[T_lo, T_hi] × S` (`S` the torque
    /// set).
    pub thrust: super::thrust::ThrustDesign,
    /// The physical choices behind the gains.
    pub choices: Choices,
    /// `M_p,max(k_f, k_s)` [m/s²].
    pub saturation_max_m_s2: f64,
    /// `ι_max` [N m] and the chosen `ι` [N m] (roll's, with tilt priority).
    pub feedback_torque_Nm: (f64, f64),
    /// The feedback torque level of each body axis `ι_i` [N m] (all equal with the paper's law).
    pub feedback_torque_axes_Nm: [f64; 3],
    /// A-priori bounds: thrust interval \[N\], per-axis torque [N m].
    pub a_priori: (f64, f64, [f64; 3]),
    /// The objective.
    pub objective: ObjectiveEntry,
    /// Margins.
    pub margins: MarginsEntry,
    /// The reference.
    pub reference: ReferenceEntry,
    /// What caps `M_p` and `ι` (docs/design.md, "What binds"); `None` until [`super::run`]
    /// fills it in.
    pub what_binds: Option<super::binding::WhatBinds>,
}

fn settling(trials: &[Trial]) -> Vec<(String, Option<f64>)> {
    trials
        .iter()
        .map(|t| (t.start.clone(), t.settling_time_s))
        .collect()
}

impl Report {
    /// Assembles the report.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        vehicle: &DesignVehicle,
        (o, law): (&DesignOptions, super::variables::AttitudeLaw),
        (requested, certified, scale, binding): (&Reference, &Reference, f64, Option<&str>),
        choices: Choices,
        best: &Scored,
        (lag_max, baselines): (Option<f64>, Vec<SanityRow>),
        evaluations: usize,
        wall_time_s: f64,
    ) -> Self {
        let c = &best.certified;
        let conditions: Vec<ConditionEntry> = c
            .certificate
            .all_conditions()
            .map(|k| {
                let tight = c.tight.iter().flatten().find(|t| t.name == k.name);
                let rhs = tight.map_or(k.rhs, |t| t.rhs_tight);
                ConditionEntry {
                    name: k.name.into(),
                    statement: k.statement.into(),
                    holds: tight.map_or(k.holds, |t| t.holds_tight),
                    lhs: k.lhs,
                    rhs,
                    slack: k.lhs - rhs,
                    paper: tight.map(|t| (t.rhs_paper, t.holds_paper)),
                }
            })
            .collect();
        let tightest = conditions
            .iter()
            .map(|k| (k.name.clone(), k.slack / k.rhs.abs().max(1e-12)))
            .fold((String::new(), f64::INFINITY), |a, b| {
                if b.1 < a.1 {
                    b
                } else {
                    a
                }
            });
        let e = &best.evaluation;
        let b = &c.certificate.bounds;
        let g = &best.mapped.gains;
        let turned = TURNED_START_ANGLES_DEG.map(|d| format!("{d:.0}")).join("/");
        Self {
            vehicle: vehicle.name.clone(),
            vehicle_source: vehicle.source.clone(),
            vehicle_file: vehicle.origin.clone(),
            seed: o.seed,
            duration_s: o.duration_s,
            evaluations,
            wall_time_s,
            fallback: match &o.fallback {
                super::options::Fallback::Taken { why, .. } => Some(why.clone()),
                _ => None,
            },
            certificate: CertificateEntry {
                bounds: o.bounds,
                lemma1: o.lemma1.name(),
                all_hold: c.all_hold(),
                paper_certified: c.paper_certified(),
                conditions,
            },
            rotor_fit: RotorFitEntry {
                shape: "set",
                fits: c.fits,
                box_fits: c.box_fit.fits,
                fits_with_margin: c.fits_with_margin,
                margin: c.margin,
                requested_margin: o.margin,
                thrust_needed_N: c.box_fit.thrust_needed,
                thrust_capacity_N: c.box_fit.thrust_capacity,
                torque_needed_Nm: c.box_fit.torque_needed,
                torque_capacity_Nm: c.limits.torque_max.map(|x| x as f32).into(),
                fit: c.fit,
                aligned_margin: c.aligned_margin,
                airmode_convergence_proven: c.aligned_margin.map(|m| m >= o.margin),
            },
            local_regime: c.certificate.local.as_ref().map(|l| LocalRegimeEntry {
                angle_out_deg: l.energy.angle.to_degrees(),
                omega_error_out_rad_s: l.energy.omega_error.into(),
                angular_acceleration_bound_rad_s2: l.bounds.angular_acceleration,
                torque_extent_Nm: l.torque_set.axis_extents().into(),
            }),
            gains: gains_config(g),
            limits: limits_config(&c.limits),
            law,
            law_search: Vec::new(),
            heading_search: Vec::new(),
            integral: o.integral,
            thrust: best.thrust.clone(),
            choices,
            saturation_max_m_s2: best.mapped.saturation_max,
            feedback_torque_Nm: (best.mapped.iota_max, b.feedback_torque),
            feedback_torque_axes_Nm: b.feedback_torque_axes.into(),
            a_priori: (b.thrust_min, b.thrust_max, c.torque_box.into()),
            objective: ObjectiveEntry {
                definition: format!(
                    "worst settling time over the seven 180 degree starts [s] + {DOUBLED_LAG_WEIGHT} x the same \
                     with the motor time constant doubled [s] + {ALTITUDE_WEIGHT_S_PER_M} s/m x \
                     altitude lost recovering from upside down at hover [m] + {NOMINAL_TASK_WEIGHT} x the \
                     settling times [s] of the 1 m step and of the 30 degree roll from hover (10 s runs; \
                     {UNSETTLED_TASK_S} s when unsettled) (+ the disturbed hover's \
                     settling time [s] + {DISTURBANCE_LOSS_WEIGHT_S_PER_M} s/m x its altitude lost [m] \
                     with the integral action), on the scenario's plant \
                     with the vehicle's motor time constant and the controller's sample-and-hold; \
                     settled: |p - p_d| < 5 cm and attitude error < 2 deg until the end; constraint: \
                     every run (also with the motor time constant doubled, and then the starts at rest \
                     turned {turned} deg from R_d(0) about the same seven axes and {RANDOM_STARTS} of the \
                     campaign's random starts, seed {RANDOM_STARTS_SEED}, with it doubled too, these \
                     {RANDOM_STARTS_MARGIN_S} s earlier) settles \
                     by the end - {TAIL_S} s with the attitude error < {TAIL_ATTITUDE_DEG} deg over the \
                     last {TAIL_S} s"
                ),
                value: e.cost,
                altitude_loss_upside_down_m: e.altitude_loss_upside_down_m,
                upside_down_turn_over: e.upside_down.turn_over,
                worst_settling_180_s: e.worst_settling_180_s,
                settling_180_s: settling(&e.nominal),
                disturbed_hover: e.disturbed_hover.as_ref().map(|t| DisturbedEntry {
                    settling_s: t.settling_time_s,
                    altitude_loss_m: t.altitude_loss_m,
                    final_position_error_m: t.final_position_error_m,
                }),
                nominal_tasks: std::iter::once(e.nominal_tasks.clone())
                    .chain(baselines)
                    .collect(),
                constraints_met: e.feasible,
                authority: AuthorityEntry {
                    thrust_interval_over_weight: [b.thrust_min, b.thrust_max]
                        .map(|t| t / (vehicle.body.mass * vehicle.body.gravity)),
                    feedback_angular_acceleration_rad_s2: <[f64; 3]>::from(
                        b.feedback_torque_axes.component_div(&vehicle.body.inertia),
                    ),
                },
            },
            margins: MarginsEntry {
                rotor_fit: c.margin,
                tightest_condition: tightest,
                motor_time_constant_s: vehicle.motor_time_constant_s,
                motor_time_constant_max_converging_s: lag_max,
                doubled_lag_converges: !e.doubled_lag.is_empty()
                    && !e.doubled_lag_turned.is_empty()
                    && !e.doubled_lag_random.is_empty()
                    && e.doubled_lag
                        .iter()
                        .chain(&e.doubled_lag_turned)
                        .chain(&e.doubled_lag_random)
                        .all(|t| t.converged),
                doubled_lag_settling_180_s: settling(&e.doubled_lag),
            },
            reference: ReferenceEntry {
                requested: requested.trajectory.clone(),
                certified: certified.trajectory.clone(),
                scaled: scale < 1.0,
                scale,
                binding: binding.map(str::to_owned),
                heading_held: o.heading_held.clone(),
            },
            what_binds: None,
            local_refinement: None,
            turn_over_refinement: None,
            local_loop_refinement: None,
            local_agility_refinement: None,
        }
    }
}
