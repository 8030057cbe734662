//! The no-dive thrust ([`controller_core::thrust`]) measured against the paper's `T = m|u|`,
//! on the same runs (the third part of `host-sim ablation`; `docs/no-dive-thrust.md`).
//!
//! - **Altitude lost** (`z(0) − min z` over the samples) from the scenario's own start, from
//!   the same start turned upright (roll and pitch 0, same yaw), from the seven starts exactly
//!   180° from `R_d(0)` of the campaign ([`HALF_TURN_AXES`], at `p_d(0)` with the reference
//!   velocity), and from the same seven starts at hover (a hover reference at `p_d(0)` with the
//!   heading `ψ_d(0)`, at rest). The **flip's cost** is the altitude lost from the scenario's
//!   start minus that of the upright start.
//! - **Chattering under attitude noise**: the seven 180° starts at hover with attitude
//!   measurement noise of [`NOISE_LEVELS_DEG`], `repeats` noise seeds each: switches of the
//!   fed-back MRP per second and the most in any 1 s, and *thrust cut-offs* (a sample whose
//!   thrust command is at the no-dive floor, `T ≤ T_floor + 1 µN`, after one above it) per
//!   second and the most in any 1 s. The paper's thrust never reaches the floor (it is at least
//!   `T_min > T_floor`), so its cut-offs are 0 by construction and are counted the same way.
//!
//! Every run flies the scenario's precision and plant; only `[controller] thrust` differs.

use anyhow::{Context, Result};
use controller_core::Trajectory;
use nalgebra::UnitQuaternion;
use rayon::prelude::*;
use serde::Serialize;

use crate::fly::closed_loop::fly;
use crate::fly::controllers::ControllerKind;
use crate::model::plant::RigidBodyState;
use crate::model::scenario::{
    ControllerConfig, HeadingConfig, Scenario, ThrustKind, TrajectoryConfig,
};
use crate::runs::metrics::{Convergence, MetricsAccumulator, WindowMax};
use crate::runs::runner::bound_set;
use crate::runs::sampler::{run_seed, Sampler, SamplerRadii, HALF_TURN_AXES};

/// Attitude noise levels of the chattering runs [deg, std per axis] (as the hysteresis
/// ablation's).
pub const NOISE_LEVELS_DEG: [f64; 3] = [0.0, 1.0, 3.0];

/// A thrust command within this of the floor counts as at the floor \[N\].
const AT_FLOOR_N: f64 = 1e-6;

/// One run's altitude figures.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct AltitudeRow {
    /// The start: `"paper_start"`, `"upright_start"`, `"half_turn_<axis>"` or
    /// `"hover_half_turn_<axis>"`.
    pub start: String,
    /// `z(0) − min z` \[m\], paper's thrust.
    pub altitude_loss_norm_m: f64,
    /// `z(0) − min z` \[m\], no-dive thrust.
    pub altitude_loss_no_dive_m: f64,
    /// Settling time (5 cm, 2°) \[s\], paper's thrust.
    pub settling_norm_s: Option<f64>,
    /// Settling time \[s\], no-dive thrust.
    pub settling_no_dive_s: Option<f64>,
}

/// One row of the chattering table.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct ChatterRow {
    /// `"norm"` or the no-dive mode's name.
    pub thrust: String,
    /// Attitude noise std \[deg\].
    pub attitude_noise_deg: f64,
    /// Runs.
    pub runs: usize,
    /// Mean over the runs of MRP switches per second of run.
    pub switches_per_s: f64,
    /// Most MRP switches in any 1 s over the runs.
    pub max_switches_in_1s: u32,
    /// Mean over the runs of thrust cut-offs per second of run.
    pub thrust_cutoffs_per_s: f64,
    /// Most thrust cut-offs in any 1 s over the runs.
    pub max_thrust_cutoffs_in_1s: u32,
    /// Runs converged (5 cm, 2°, settled by 25 s).
    pub converged: usize,
}

/// `ablation.json`'s `no_dive_thrust`.
#[derive(Clone, Debug, Serialize, PartialEq)]
#[allow(non_snake_case)]
pub struct NoDiveReport {
    /// Definitions of the measured quantities.
    pub definitions: String,
    /// The no-dive mode measured (the scenario's `[controller]`, or `vertical-priority` when the
    /// scenario flies the paper's thrust).
    pub no_dive: ControllerConfig,
    /// Its certified thrust interval `[T_floor, T_max]` \[N\].
    pub no_dive_thrust_interval_N: [f64; 2],
    /// The flip's cost \[m\] with the paper's thrust: paper start minus upright start.
    pub flip_cost_norm_m: f64,
    /// The flip's cost \[m\] with the no-dive thrust.
    pub flip_cost_no_dive_m: f64,
    /// Every start.
    pub altitude: Vec<AltitudeRow>,
    /// Chattering under attitude noise.
    pub chattering: Vec<ChatterRow>,
    /// `(t [s], z [m])` of the paper start (norm, no-dive) and the upright start (norm), for
    /// the plot.
    #[serde(skip)]
    pub altitude_traces: Vec<(String, Vec<(f64, f64)>)>,
}

/// What one run gives.
struct Flown {
    altitude_loss_m: f64,
    settling_s: Option<f64>,
    converged: bool,
    duration_s: f64,
    switches: u32,
    max_switches_in_1s: u32,
    cutoffs: u32,
    max_cutoffs_in_1s: u32,
    trace: Vec<(f64, f64)>,
}

/// Flies `scenario` from `initial` (noise drawn from `seed`), with the thrust floor `floor` \[N\]
/// for the cut-off count.
fn fly_one(
    scenario: &Scenario,
    initial: &RigidBodyState,
    seed: u64,
    floor: f64,
    keep_trace: bool,
) -> Result<Flown> {
    fly_one_with(
        scenario,
        bound_set(scenario)?,
        initial,
        seed,
        floor,
        keep_trace,
    )
}

/// [`fly_one`] with the bounds its metrics count against given.
fn fly_one_with(
    scenario: &Scenario,
    bounds: crate::runs::metrics::BoundSet,
    initial: &RigidBodyState,
    seed: u64,
    floor: f64,
    keep_trace: bool,
) -> Result<Flown> {
    let sim = &scenario.simulation;
    let mut acc = MetricsAccumulator::new(
        Convergence::default(),
        bounds,
        sim.duration_s,
        sim.controller_period_s,
    );
    let window = (1.0 / sim.controller_period_s).round() as usize;
    let mut cutoff_window = WindowMax::new(window);
    // A run that starts at the floor counts that first cut-off in its first second too.
    cutoff_window.push(0);
    let (mut cutoffs, mut above, mut z_min) = (0u32, true, initial.position.z);
    let mut trace = Vec::new();
    let mut law = ControllerKind::Paper.build(scenario)?;
    fly(scenario, law.as_mut(), initial, seed, |s| {
        acc.push(s);
        let at_floor = s.command.thrust <= floor + AT_FLOOR_N;
        cutoffs += u32::from(at_floor && above);
        above = !at_floor;
        cutoff_window.push(cutoffs);
        z_min = z_min.min(s.state.position.z);
        if keep_trace {
            trace.push((s.t, s.state.position.z));
        }
    })?;
    let m = acc.finish();
    Ok(Flown {
        altitude_loss_m: (initial.position.z - z_min).max(0.0),
        settling_s: m.settling_time_s,
        converged: m.converged,
        duration_s: sim.duration_s,
        switches: m.switches,
        max_switches_in_1s: m.max_switches_per_1s,
        cutoffs,
        max_cutoffs_in_1s: cutoff_window.max,
        trace,
    })
}

/// `scenario` with a hover reference at `p_d(0)` and the constant heading `ψ_d(0)`.
pub fn hover_at_start(scenario: &Scenario) -> Scenario {
    let start = scenario.trajectory::<f64>().sample(0.0);
    let mut s = scenario.clone();
    s.trajectory = TrajectoryConfig::Hover {
        point_m: start.position.into(),
        heading: HeadingConfig::Constant {
            yaw_rad: start.yaw(),
        },
    };
    s
}

/// The scenario's start turned upright: roll and pitch 0, same yaw, same position and velocity.
pub fn upright(scenario: &Scenario) -> RigidBodyState {
    let mut s = scenario.initial_state();
    let [_, _, yaw] = scenario.initial.euler_deg.map(f64::to_radians);
    s.attitude = UnitQuaternion::from_euler_angles(0.0, 0.0, yaw);
    s
}

/// The seven 180° starts of `scenario` (zero offsets), with their labels.
fn half_turn_starts(scenario: &Scenario) -> Result<Vec<(String, RigidBodyState)>> {
    let zero = SamplerRadii {
        position_m: 0.0,
        velocity_m_s: 0.0,
        angular_velocity_rad_s: 0.0,
    };
    let sampler = Sampler::new(scenario, zero)?;
    Ok((0..HALF_TURN_AXES.len() as u64)
        .map(|i| {
            let ic = sampler.sample(i, 0, true);
            (ic.kind.label(), ic.state)
        })
        .collect())
}

/// Altitude lost \[m\] and settling time \[s\] (5 cm, 2°; `None` if not settled) from the seven
/// 180° starts of `scenario` against a hover at its start ([`hover_at_start`]), at rest, no
/// noise, with the scenario's own law; labelled as the campaign labels them.
/// Errors: the scenario is invalid or a run fails.
pub fn hover_half_turns(scenario: &Scenario) -> Result<Vec<(String, f64, Option<f64>)>> {
    let hover = hover_at_start(scenario);
    // Only the altitude and the settling are kept: the paper's bounds (no branch and bound).
    let bounds = crate::runs::runner::paper_bound_set(&hover)?;
    half_turn_starts(&hover)?
        .into_iter()
        .map(|(label, start)| {
            let f = fly_one_with(&hover, bounds, &start, 0, 0.0, false)?;
            Ok((label, f.altitude_loss_m, f.settling_s))
        })
        .collect()
}

/// The no-dive configuration measured for `scenario`: its own `[controller]` if it departs
/// from the paper, else vertical priority with the default ramp (the recommended no-dive
/// thrust, `docs/no-dive-thrust.md`).
pub fn no_dive_config(scenario: &Scenario) -> ControllerConfig {
    if scenario.controller.is_paper() {
        ControllerConfig {
            thrust: ThrustKind::VerticalPriority,
            ..ControllerConfig::default()
        }
    } else {
        scenario.controller
    }
}

/// Measures the no-dive thrust against the paper's on `scenario` (see the module docs);
/// `seed` draws the noise, `repeats` noise seeds per start and level.
///
/// Errors: the scenario is invalid (bounds, `R_d(0)`), the floor is above `T_min`, or a run
/// is refused.
pub fn run_no_dive(scenario: &Scenario, seed: u64, repeats: u64) -> Result<NoDiveReport> {
    let no_dive = no_dive_config(scenario);
    let with = |base: &Scenario, controller: ControllerConfig| Scenario {
        controller,
        ..base.clone()
    };
    let modes = [ControllerConfig::default(), no_dive];
    let no_dive_scenario = with(scenario, no_dive);
    let cert = crate::fly::sim::certificate(&no_dive_scenario)?;
    let interval_no_dive = no_dive_scenario
        .thrust_interval(&cert)
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    let floor = interval_no_dive[0];

    let hover = hover_at_start(scenario);
    let mut starts: Vec<(String, &Scenario, RigidBodyState)> = vec![
        ("paper_start".into(), scenario, scenario.initial_state()),
        ("upright_start".into(), scenario, upright(scenario)),
    ];
    for (label, state) in half_turn_starts(scenario)? {
        starts.push((label, scenario, state));
    }
    for (label, state) in half_turn_starts(&hover)? {
        starts.push((format!("hover_{label}"), &hover, state));
    }
    let flown: Vec<[Flown; 2]> = starts
        .par_iter()
        .map(|(label, base, initial)| {
            let one = |c: ControllerConfig| {
                let keep = label == "paper_start" || label == "upright_start";
                fly_one(&with(base, c), initial, 0, floor, keep)
                    .with_context(|| format!("{label}, thrust = {}", c.thrust.name()))
            };
            Ok([one(modes[0])?, one(modes[1])?])
        })
        .collect::<Result<_>>()?;
    let altitude: Vec<AltitudeRow> = starts
        .iter()
        .zip(&flown)
        .map(|((label, _, _), [n, d])| AltitudeRow {
            start: label.clone(),
            altitude_loss_norm_m: n.altitude_loss_m,
            altitude_loss_no_dive_m: d.altitude_loss_m,
            settling_norm_s: n.settling_s,
            settling_no_dive_s: d.settling_s,
        })
        .collect();
    let altitude_traces = vec![
        (
            "paper start, T = m|u|".to_string(),
            flown[0][0].trace.clone(),
        ),
        (
            format!("paper start, {}", no_dive.thrust.name()),
            flown[0][1].trace.clone(),
        ),
        ("upright start".to_string(), flown[1][0].trace.clone()),
    ];
    let flip_cost = |k: usize| flown[0][k].altitude_loss_m - flown[1][k].altitude_loss_m;

    let hover_starts = half_turn_starts(&hover)?;
    let mut chattering = Vec::new();
    for noise in NOISE_LEVELS_DEG {
        for c in modes {
            let mut s = with(&hover, c);
            s.perturbations.attitude_noise_std_rad = noise.to_radians();
            let axes = hover_starts.len() as u64;
            let runs: Vec<Flown> = (0..repeats * axes)
                .into_par_iter()
                .map(|i| {
                    let (label, initial) = &hover_starts[(i % axes) as usize];
                    fly_one(&s, initial, run_seed(seed, i), floor, false)
                        .with_context(|| format!("hover {label}, noise {noise} deg"))
                })
                .collect::<Result<_>>()?;
            let mean =
                |f: fn(&Flown) -> f64| runs.iter().map(f).sum::<f64>() / (runs.len().max(1) as f64);
            chattering.push(ChatterRow {
                thrust: c.thrust.name().into(),
                attitude_noise_deg: noise,
                runs: runs.len(),
                switches_per_s: mean(|r| f64::from(r.switches) / r.duration_s),
                max_switches_in_1s: runs.iter().map(|r| r.max_switches_in_1s).max().unwrap_or(0),
                thrust_cutoffs_per_s: mean(|r| f64::from(r.cutoffs) / r.duration_s),
                max_thrust_cutoffs_in_1s: runs
                    .iter()
                    .map(|r| r.max_cutoffs_in_1s)
                    .max()
                    .unwrap_or(0),
                converged: runs.iter().filter(|r| r.converged).count(),
            });
        }
    }
    Ok(NoDiveReport {
        definitions: format!(
            "altitude loss: z(0) - min z over the controller samples. flip cost: altitude loss \
             from the scenario's start minus that from the same start turned upright (roll = \
             pitch = 0, same yaw). half_turn_<axis>: the campaign's starts exactly 180 deg from \
             R_d(0) at p_d(0) with the reference velocity; hover_half_turn_<axis>: the same \
             against a hover reference at p_d(0) with heading psi_d(0), at rest. Chattering: \
             the hover 180-deg starts with attitude measurement noise, {repeats} seeds each; \
             switches: MRP/shadow-MRP flips of the fed-back error; thrust cut-offs: samples \
             whose thrust command is at the no-dive floor ({floor} N, within {AT_FLOOR_N} N) \
             after one above it. Only [controller] thrust differs between the two columns."
        ),
        no_dive,
        no_dive_thrust_interval_N: interval_no_dive,
        flip_cost_norm_m: flip_cost(0),
        flip_cost_no_dive_m: flip_cost(1),
        altitude,
        chattering,
        altitude_traces,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    /// The upright start keeps the position and yaw, and its body z axis is vertical.
    #[test]
    fn upright_start_is_level_with_the_same_yaw() {
        let s = Scenario::paper();
        let u = upright(&s);
        let body_z = u.attitude * Vector3::z();
        assert!((body_z - Vector3::z()).norm() < 1e-12);
        assert_eq!(u.position, s.initial_state().position);
        let (_, _, yaw) = u.attitude.euler_angles();
        assert!((yaw - 100f64.to_radians()).abs() < 1e-12);
    }

    /// From the paper's start, the no-dive thrust loses less altitude than the paper's, and
    /// the certified interval is [0, T_max] and is respected by every sample.
    #[test]
    fn no_dive_loses_less_altitude_from_the_paper_start() {
        let mut s = Scenario::paper();
        s.simulation.duration_s = 8.0;
        let norm = fly_one(&s, &s.initial_state(), 0, 0.0, false).unwrap();
        let d = Scenario {
            controller: no_dive_config(&s),
            ..s.clone()
        };
        let nd = fly_one(&d, &d.initial_state(), 0, 0.0, false).unwrap();
        assert!(
            nd.altitude_loss_m < 0.8 * norm.altitude_loss_m,
            "{} vs {}",
            nd.altitude_loss_m,
            norm.altitude_loss_m
        );
        // Inverted at the start: the no-dive thrust is cut off at least once, the paper's never.
        assert!(nd.cutoffs >= 1);
        assert_eq!(norm.cutoffs, 0);
    }

    /// The main run of `paper-no-dive.toml`: its summary names the certified interval
    /// [0, Theorem 1's T_max], the thrust reaches both ends and no sample leaves it; the
    /// altitude lost is the samples' `z(0) − min z`.
    #[test]
    fn main_run_reports_the_no_dive_interval_and_the_altitude_lost() {
        let mut s = Scenario::parse(
            include_str!("../../../scenarios/paper-no-dive.toml"),
            "paper-no-dive.toml",
        )
        .unwrap();
        s.simulation.duration_s = 6.0;
        let (summary, records) = crate::fly::sim::run(&s).unwrap();
        let t_max = crate::fly::sim::certificate(&s).unwrap().bounds.thrust_max;
        assert_eq!(
            summary.a_priori.no_dive_thrust_interval_N,
            Some([0.0, t_max])
        );
        assert_eq!(summary.observed.samples_outside_a_priori_bounds, 0);
        assert_eq!(summary.observed.thrust_min_N, 0.0);
        assert!(summary.observed.thrust_max_N <= t_max * (1.0 + 1e-6));
        let z_min = records.iter().map(|r| r.z_m).fold(f64::INFINITY, f64::min);
        assert_eq!(summary.observed.altitude_loss_m, records[0].z_m - z_min);
    }
}
