//! Files of a campaign: `campaign.json`, `runs.csv` and the PNG plots.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use serde::Serialize;

use super::figures::{cdf_points, histogram, xy_figure, Axis, Style, XySeries, PALETTE};
use crate::model::perturbation::PerturbationConfig;
use crate::runs::metrics::{BoundSet, Convergence};
use crate::runs::runner::{CampaignConfig, RunResult};
use crate::runs::sampler::{SamplerRadii, HALF_TURN_AXES};
use crate::runs::stats::CampaignStats;

/// The definitions used, in words and numbers.
#[derive(Clone, Debug, Serialize)]
pub struct Definitions {
    /// Convergence and settling time.
    pub converged: String,
    /// The thresholds.
    pub thresholds: Convergence,
    /// What counts as outside the bounds.
    pub bound_check: String,
    /// Which runs are "nominal".
    pub nominal: String,
    /// The sampled initial conditions.
    pub initial_conditions: String,
    /// Switch counting.
    pub switches: String,
    /// What the mixer counts mean (rotor plant only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mixer: Option<String>,
}

/// `campaign.json`: a function of the set-up alone (no wall time), so a campaign gives the
/// same bytes on any machine, with any thread count and split into any shards.
#[derive(Clone, Debug, Serialize)]
pub struct CampaignReport {
    /// Controller flown.
    pub controller: String,
    /// Runs.
    pub runs: u64,
    /// Campaign seed.
    pub seed: u64,
    /// Simulated duration per run \[s\].
    pub duration_s: f64,
    /// Controller period \[s\].
    pub controller_period_s: f64,
    /// Controller precision.
    pub precision: crate::model::scenario::Precision,
    /// The plant flown (`"ideal"` or `"rotors"`).
    pub plant: crate::model::scenario::PlantKind,
    /// The law's `[controller]` options (absent: the paper's law, `T = m|u|`).
    #[serde(skip_serializing_if = "crate::model::scenario::ControllerConfig::is_paper")]
    pub controller_options: crate::model::scenario::ControllerConfig,
    /// Commands clipped to the physical limits before the plant.
    pub clip_to_limits: bool,
    /// The perturbations of every run.
    pub perturbations: PerturbationConfig,
    /// Offset ball radii.
    pub sampler_radii: SamplerRadii,
    /// Definitions.
    pub definitions: Definitions,
    /// A-priori bounds and physical limits.
    pub bounds: BoundSet,
    /// Results.
    pub results: CampaignStats,
}

impl CampaignReport {
    /// Assembles the report.
    pub fn new(config: &CampaignConfig, bounds: BoundSet, results: CampaignStats) -> Self {
        let s = &config.scenario;
        Self {
            controller: config.controller.label().into(),
            runs: config.runs,
            seed: config.seed,
            duration_s: s.simulation.duration_s,
            controller_period_s: s.simulation.controller_period_s,
            precision: s.simulation.precision,
            plant: s.simulation.plant,
            controller_options: s.controller,
            clip_to_limits: s.simulation.clip_to_limits,
            perturbations: s.perturbations.clone(),
            sampler_radii: config.radii,
            definitions: Definitions {
                converged: config.convergence.describe(),
                thresholds: config.convergence,
                bound_check: "a sample is outside the a-priori bounds when the commanded thrust \
                    (before any clipping) leaves [T_min, T_max] of Theorem 1 or some |tau_i| \
                    exceeds Theorem 2's per-axis bound (relative slack 1e-5); beyond the limits \
                    when T < 0, T > thrust_max_N or |tau_i| > torque_max_Nm. The a-priori bounds \
                    are the paper law's; for other controllers only the limits are meaningful. \
                    With a no-dive thrust ([controller] thrust), the thrust interval is that \
                    mode's certified one (bounds.thrust_min_N: T_floor or 0)."
                    .into(),
                nominal: "nominal runs: no model error, disturbance or motor lag (measurement \
                    noise allowed: the bounds come from the saturations and hold for any \
                    measured state). Samples outside the a-priori bounds must be 0 there; in \
                    perturbed runs they are information, not a failure."
                    .into(),
                initial_conditions: format!(
                    "runs 0..{} (when half turns are on): attitude exactly 180 deg from R_d(0) \
                    about the desired-body axes {:?}, zero angular velocity, reference velocity; \
                    other runs: Haar-uniform attitude, velocity offset and body angular velocity \
                    uniform in balls; every run: position offset uniform in a ball around \
                    p_d(0). Run i draws from ChaCha8 seeded with splitmix(seed, i).",
                    HALF_TURN_AXES.len(),
                    HALF_TURN_AXES.map(|a| a.0)
                ),
                switches: "switches: jumps of the attitude error fed back (paper: MRP flips \
                    between principal and shadow MRP; memoryless/PX4: changes of the q0 >= 0 \
                    hemisphere between samples); resets: the paper's memory-quaternion resets \
                    (the fed-back MRP is continuous across them)."
                    .into(),
                mixer: (!s.simulation.plant.is_ideal()).then(|| {
                    "results.mixer: samples whose command (after any clipping) the firmware's \
                    mixer could not realise on the rotors (it scaled roll/pitch, shifted the \
                    collective or scaled yaw), and the largest thrust [N] and per-axis torque \
                    [N m] it gave up in one sample; split like the bound counts. Nominal runs \
                    must give up nothing for the certified box to be flyable."
                        .into()
                }),
            },
            bounds,
            results,
        }
    }
}

/// One `runs.csv` row.
#[derive(Serialize)]
#[allow(non_snake_case)]
struct Row<'a> {
    index: u64,
    seed: u64,
    start: &'a str,
    initial_attitude_error_deg: f64,
    initial_position_error_m: f64,
    converged: bool,
    settling_time_s: Option<f64>,
    attitude_below_90deg_s: Option<f64>,
    final_position_error_m: Option<f64>,
    final_attitude_error_deg: Option<f64>,
    steady_position_error_m: Option<f64>,
    thrust_min_N: Option<f64>,
    thrust_max_N: Option<f64>,
    torque_abs_max_x_Nm: Option<f64>,
    torque_abs_max_y_Nm: Option<f64>,
    torque_abs_max_z_Nm: Option<f64>,
    samples_outside_a_priori: Option<u64>,
    samples_above_tight: Option<u64>,
    samples_beyond_limits: Option<u64>,
    omega_d_max_rad_s: Option<f64>,
    omega_d_dot_max_rad_s2: Option<f64>,
    switches: Option<u32>,
    resets: Option<u32>,
    max_switches_per_1s: Option<u32>,
    max_jumps_per_1s: Option<u32>,
    mixer_samples_given_up: Option<u64>,
    mixer_thrust_given_up_max_N: Option<f64>,
    mixer_torque_given_up_max_Nm: Option<f64>,
    error: Option<&'a str>,
}

/// Writes `runs.csv`, one row per run (units in the column names).
///
/// Errors: the file cannot be written (named).
pub fn write_runs_csv(path: &Path, results: &[RunResult]) -> Result<()> {
    let ctx = || format!("writing {}", path.display());
    let mut w = csv::Writer::from_path(path).with_context(ctx)?;
    for r in results {
        let m = r.metrics.as_ref();
        w.serialize(Row {
            index: r.index,
            seed: r.seed,
            start: &r.start,
            initial_attitude_error_deg: r.initial_attitude_error_deg,
            initial_position_error_m: r.initial_position_error_m,
            converged: m.is_some_and(|m| m.converged),
            settling_time_s: m.and_then(|m| m.settling_time_s),
            attitude_below_90deg_s: m.and_then(|m| m.attitude_below_90deg_s),
            final_position_error_m: m.map(|m| m.final_position_error_m),
            final_attitude_error_deg: m.map(|m| m.final_attitude_error_deg),
            steady_position_error_m: m.map(|m| m.steady_position_error_m),
            thrust_min_N: m.map(|m| m.thrust_min_N),
            thrust_max_N: m.map(|m| m.thrust_max_N),
            torque_abs_max_x_Nm: m.map(|m| m.torque_abs_max_Nm[0]),
            torque_abs_max_y_Nm: m.map(|m| m.torque_abs_max_Nm[1]),
            torque_abs_max_z_Nm: m.map(|m| m.torque_abs_max_Nm[2]),
            samples_outside_a_priori: m.map(|m| m.samples_outside_a_priori),
            samples_above_tight: m.map(|m| m.samples_above_tight),
            samples_beyond_limits: m.map(|m| m.samples_beyond_limits),
            omega_d_max_rad_s: m.map(|m| m.omega_d_max_rad_s),
            omega_d_dot_max_rad_s2: m.map(|m| m.omega_d_dot_max_rad_s2),
            switches: m.map(|m| m.switches),
            resets: m.map(|m| m.resets),
            max_switches_per_1s: m.map(|m| m.max_switches_per_1s),
            max_jumps_per_1s: m.map(|m| m.max_jumps_per_1s),
            mixer_samples_given_up: m.and_then(|m| m.mixer).map(|x| x.samples_given_up),
            mixer_thrust_given_up_max_N: m.and_then(|m| m.mixer).map(|x| x.thrust_given_up_max_N),
            mixer_torque_given_up_max_Nm: m.and_then(|m| m.mixer).map(|x| x.torque_given_up_max_Nm),
            error: r.error.as_deref(),
        })
        .with_context(ctx)?;
    }
    w.flush().with_context(ctx)?;
    Ok(())
}

/// Writes `campaign.json`, `runs.csv` and the plots into `dir` (created if missing); returns
/// the paths written.
///
/// Errors: a file cannot be written (named).
pub fn write_campaign(
    dir: &Path,
    report: &CampaignReport,
    results: &[RunResult],
    plots: bool,
) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let json = dir.join("campaign.json");
    let text = serde_json::to_string_pretty(report)?;
    std::fs::write(&json, text + "\n").with_context(|| format!("writing {}", json.display()))?;
    let csv = dir.join("runs.csv");
    write_runs_csv(&csv, results)?;
    let mut written = vec![json, csv];
    if plots {
        written.extend(write_campaign_plots(dir, report, results)?);
    }
    Ok(written)
}

/// The four campaign plots.
fn write_campaign_plots(
    dir: &Path,
    report: &CampaignReport,
    results: &[RunResult],
) -> Result<Vec<PathBuf>> {
    let ok: Vec<_> = results.iter().filter_map(|r| r.metrics.as_ref()).collect();
    let settling: Vec<f64> = ok.iter().filter_map(|m| m.settling_time_s).collect();
    let duration = report.duration_s;
    let name = &report.controller;
    let mut written = Vec::new();

    let path = dir.join("settling_histogram.png");
    histogram(
        &path,
        &format!(
            "Settling time, {name} ({} of {} runs settled)",
            settling.len(),
            results.len()
        ),
        "settling time [s]",
        &settling,
        30,
        Some((0.0, duration)),
    )?;
    written.push(path);

    let path = dir.join("settling_cdf.png");
    let limit = report.definitions.thresholds.after_s;
    xy_figure(
        &path,
        &format!("Fraction of runs settled by t, {name}"),
        &Axis::linear("t [s]"),
        &Axis::linear("fraction of runs"),
        &[
            XySeries {
                label: "settled".into(),
                color: PALETTE[0],
                style: Style::Line,
                points: cdf_points(&settling, results.len(), duration),
            },
            XySeries {
                label: format!("convergence deadline {limit} s"),
                color: PALETTE[5],
                style: Style::Dashed,
                points: vec![(limit, 0.0), (limit, 1.0)],
            },
        ],
    )?;
    written.push(path);

    // Worst cases per run, sorted, against the a-priori bounds and the limits.
    let b = &report.bounds;
    let n = ok.len().max(1) as f64;
    let sorted = |f: &dyn Fn(&&crate::runs::metrics::RunMetrics) -> f64| {
        let mut v: Vec<f64> = ok.iter().map(f).collect();
        v.sort_by(f64::total_cmp);
        v.into_iter()
            .enumerate()
            .map(|(i, y)| ((i as f64 + 1.0) / n, y))
            .collect::<Vec<_>>()
    };
    let level = |label: String, y: f64, color| XySeries {
        label,
        color,
        style: Style::Dashed,
        points: vec![(0.0, y), (1.0, y)],
    };
    let path = dir.join("worst_thrust.png");
    xy_figure(
        &path,
        &format!("Per-run thrust extremes (sorted), {name}"),
        &Axis::linear("fraction of runs"),
        &Axis::linear("thrust [N]"),
        &[
            XySeries {
                label: "largest T per run".into(),
                color: PALETTE[0],
                style: Style::Line,
                points: sorted(&|m| m.thrust_max_N),
            },
            XySeries {
                label: "smallest T per run".into(),
                color: PALETTE[2],
                style: Style::Line,
                points: sorted(&|m| m.thrust_min_N),
            },
            level(
                format!("a-priori [{:.2}, {:.2}] N", b.thrust_min_N, b.thrust_max_N),
                b.thrust_max_N,
                PALETTE[1],
            ),
            level(String::new(), b.thrust_min_N, PALETTE[1]),
            level(
                format!("limit {} N", b.limit_thrust_N),
                b.limit_thrust_N,
                PALETTE[5],
            ),
        ],
    )?;
    written.push(path);

    let path = dir.join("worst_torque.png");
    let mut series = Vec::new();
    for (i, axis) in ["x", "y", "z"].iter().enumerate() {
        series.push(XySeries {
            label: format!("largest |tau_{axis}| per run"),
            color: PALETTE[i],
            style: Style::Line,
            points: sorted(&|m| m.torque_abs_max_Nm[i]),
        });
        series.push(level(
            format!("a-priori bound {axis}: {:.3} N m", b.torque_max_Nm[i]),
            b.torque_max_Nm[i],
            PALETTE[i],
        ));
    }
    series.push(level(
        format!("limit {} N m", b.limit_torque_Nm[0]),
        b.limit_torque_Nm[0],
        PALETTE[5],
    ));
    xy_figure(
        &path,
        &format!("Per-run torque extremes (sorted), {name}"),
        &Axis::linear("fraction of runs"),
        &Axis::linear("torque [N m]"),
        &series,
    )?;
    written.push(path);

    let path = dir.join("final_error_scatter.png");
    xy_figure(
        &path,
        &format!("Final errors at t = {duration} s, {name}"),
        &Axis::log("|p - p_d| [m]"),
        &Axis::log("attitude error [deg]"),
        &[XySeries {
            label: "one run".into(),
            color: PALETTE[0],
            style: Style::Points,
            points: ok
                .iter()
                .map(|m| (m.final_position_error_m, m.final_attitude_error_deg))
                .collect(),
        }],
    )?;
    written.push(path);
    Ok(written)
}
