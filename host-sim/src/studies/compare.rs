//! `host-sim compare`: the paper's law against the baselines on the same runs, as a markdown
//! report with tables and embedded plots (`compare.md`), plus `compare.json`.
//!
//! Contestants: the paper's law (controller-core, the scenario's precision), Lee et al. (2010)
//! unclipped and with the commands clipped to the physical limits, and the PX4-style cascade
//! (which clips its own outputs). Every contestant flies the same initial conditions and the same
//! noise draws (seeds derive from the campaign seed and the run index only).
//!
//! Sections: the baselines' own sanity checks (hover, 1 m step); the seven 180° starts; a
//! campaign (Haar attitudes, offsets in balls); chattering under attitude noise at 180°.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use nalgebra::Vector3;
use rayon::prelude::*;
use serde::Serialize;

use crate::fly::controllers::ControllerKind;
use crate::model::plant::RigidBodyState;
use crate::model::scenario::{HeadingConfig, Scenario, TrajectoryConfig};
use crate::output::chart::{LegendAt, Panel, Scale, Series};
use crate::output::console::fmt_opt;
use crate::runs::metrics::{BoundSet, RunMetrics};
use crate::runs::runner::{bound_set, run_one, RunResult};
use crate::runs::sampler::{run_seed, Sampler, SamplerRadii, HALF_TURN_AXES};
use crate::runs::stats::{summarise, CampaignStats};
use crate::runs::trace::trace;
use crate::studies::ablation::integral::convergence_of;
use crate::studies::campaign::figures::{
    cdf_points, time_series_png, xy_figure, Axis, Style, XySeries, PALETTE,
};
use crate::studies::campaign::options::BaseOptions;
use crate::studies::campaign::{run_campaign, CampaignConfig, Convergence};

/// One contestant: a controller, whether the plant clips its commands, and whether the
/// paper's law flies the scenario's bounded integral action.
#[derive(Clone, Debug, Serialize)]
pub struct Contestant {
    /// Report label.
    pub label: String,
    /// Controller.
    pub controller: ControllerKind,
    /// Commands clipped to the physical limits before the plant.
    pub clip: bool,
    /// The scenario's `[gains.integral]` is kept (`false`: removed, so the law, its thrust cap
    /// and its bounds are the paper's). Only the paper's law reads it.
    pub integral: bool,
}

impl Contestant {
    /// The scenario this contestant flies: `base` with its clipping and, without the integral
    /// action, `[gains.integral]` removed.
    pub fn scenario(&self, base: &Scenario) -> Scenario {
        let mut s = base.clone();
        s.simulation.clip_to_limits = self.clip;
        if !self.integral {
            s.gains.integral = None;
        }
        s
    }
}

/// The contestants for a base scenario: the paper's law (with and without the bounded integral
/// action when the scenario has one, docs/integral-action.md), Lee et al. unclipped and clipped,
/// and the PX4-style cascade.
pub fn contestants(scenario: &Scenario) -> Vec<Contestant> {
    let clip = scenario.simulation.clip_to_limits;
    let c = |label: &str, controller, clip, integral| Contestant {
        label: label.into(),
        controller,
        clip,
        integral,
    };
    let mut list = Vec::new();
    if scenario.gains.integral.is_some() {
        list.push(c("paper + integral", ControllerKind::Paper, clip, true));
    }
    list.extend([
        c("paper", ControllerKind::Paper, clip, false),
        c("lee", ControllerKind::Lee, clip, false),
        c("lee (clipped)", ControllerKind::Lee, true, false),
        c("px4", ControllerKind::Px4, clip, false),
    ]);
    list
}

/// Hover and step checks of one contestant.
#[derive(Clone, Debug, Serialize)]
pub struct SanityRow {
    /// Contestant.
    pub label: String,
    /// Hover: position error after 10 s \[m\].
    pub hover_final_position_error_m: f64,
    /// 1 m horizontal step: settling time \[s\].
    pub step_settling_time_s: Option<f64>,
    /// 1 m horizontal step: position error after 10 s \[m\].
    pub step_final_position_error_m: f64,
    /// 30° roll step: settling time \[s\].
    pub tilt_settling_time_s: Option<f64>,
}

/// One contestant's results.
#[derive(Clone, Debug, Serialize)]
pub struct ContestantResult {
    /// Contestant.
    pub contestant: Contestant,
    /// Sanity checks.
    pub sanity: SanityRow,
    /// The seven 180° starts (10 m ball).
    pub half_turns: CampaignStats,
    /// The campaign.
    pub campaign: CampaignStats,
    /// Chattering runs: 180° starts at the reference with attitude noise.
    pub chattering: CampaignStats,
    /// The bounds this contestant's samples are checked against: the extended certificate's
    /// with the integral action, the paper's without (the report's `bounds` otherwise).
    pub bounds: BoundSet,
}

/// `compare.json`.
#[derive(Clone, Debug, Serialize)]
pub struct CompareReport {
    /// Campaign runs per contestant.
    pub runs: u64,
    /// Seed.
    pub seed: u64,
    /// Attitude noise of the chattering runs \[deg\].
    pub chattering_noise_deg: f64,
    /// The plant every contestant flies (with `"rotors"`, every controller's `(T, τ)` goes
    /// through the firmware's mixer and the rotors).
    pub plant: crate::model::scenario::PlantKind,
    /// Definitions.
    pub definitions: String,
    /// Bounds and limits.
    pub bounds: BoundSet,
    /// Results per contestant.
    pub results: Vec<ContestantResult>,
}

/// Attitude noise of the chattering comparison [deg per axis].
pub const CHATTER_NOISE_DEG: f64 = 2.0;

/// Hover, 1 m step and 30° tilt from hover at (0, 0, 5) m, 10 s each.
fn sanity(base: &Scenario, c: &Contestant, bounds: BoundSet) -> Result<SanityRow> {
    let mut s = c.scenario(base);
    s.trajectory = TrajectoryConfig::Hover {
        point_m: [0.0, 0.0, 5.0],
        heading: HeadingConfig::Constant { yaw_rad: 0.0 },
    };
    s.simulation.duration_s = 10.0;
    let conv = Convergence {
        after_s: 10.0,
        ..Convergence::default()
    };
    let at = |p: Vector3<f64>, attitude| RigidBodyState {
        position: p,
        velocity: Vector3::zeros(),
        attitude,
        angular_velocity: Vector3::zeros(),
    };
    let hover_point = Vector3::new(0.0, 0.0, 5.0);
    let level = nalgebra::UnitQuaternion::identity();
    let run = |initial: RigidBodyState| -> Result<RunMetrics> {
        Ok(trace(&s, c.controller, &initial, 0, conv, bounds)?.0)
    };
    let hover = run(at(hover_point, level))?;
    let step = run(at(hover_point + Vector3::x(), level))?;
    let tilt = run(at(
        hover_point,
        nalgebra::UnitQuaternion::from_euler_angles(30f64.to_radians(), 0.0, 0.0),
    ))?;
    Ok(SanityRow {
        label: c.label.clone(),
        hover_final_position_error_m: hover.final_position_error_m,
        step_settling_time_s: step.settling_time_s,
        step_final_position_error_m: step.final_position_error_m,
        tilt_settling_time_s: tilt.settling_time_s,
    })
}

fn chattering(
    base: &Scenario,
    c: &Contestant,
    seed: u64,
    bounds: BoundSet,
) -> Result<CampaignStats> {
    let mut s = c.scenario(base);
    s.perturbations.attitude_noise_std_rad = CHATTER_NOISE_DEG.to_radians();
    let radii = SamplerRadii {
        position_m: 0.0,
        velocity_m_s: 0.0,
        angular_velocity_rad_s: 0.0,
    };
    let sampler = Sampler::new(&s, radii)?;
    let axes = HALF_TURN_AXES.len() as u64;
    let results: Vec<RunResult> = (0..2 * axes)
        .into_par_iter()
        .map(|i| {
            let seed = run_seed(seed, i);
            let initial = sampler.sample(i % axes, seed, true);
            run_one(
                &s,
                c.controller,
                i,
                seed,
                &initial,
                convergence_of(base),
                bounds,
            )
        })
        .collect();
    Ok(summarise(&results, true))
}

/// Runs the whole comparison; also returns each contestant's campaign settling times. Runs are
/// judged as `campaign` judges them, 5 s before the end of the scenario's runs
/// ([`convergence_of`]: 25 s into the paper's 30 s).
///
/// Errors: invalid scenario, or a sanity run the controller refused.
pub fn run_compare(
    base: &Scenario,
    runs: u64,
    seed: u64,
) -> Result<(CompareReport, Vec<Vec<RunResult>>)> {
    let bounds = bound_set(base)?;
    let mut results = Vec::new();
    let mut campaigns = Vec::new();
    for c in contestants(base) {
        let s = c.scenario(base);
        // Without the integral action the law's bounds are the paper's, not the extended ones.
        let own_bounds = if c.integral || base.gains.integral.is_none() {
            bounds
        } else {
            bound_set(&s)?
        };
        let config = |runs, radii| CampaignConfig {
            scenario: s.clone(),
            controller: c.controller,
            runs,
            seed,
            radii,
            half_turns: true,
            convergence: convergence_of(base),
            progress: true,
            threads: None,
        };
        let nominal = !s.perturbations.violates_model();
        let half = run_campaign(&config(
            HALF_TURN_AXES.len() as u64,
            SamplerRadii::default(),
        ))?;
        let campaign = run_campaign(&config(runs, SamplerRadii::default()))?;
        results.push(ContestantResult {
            sanity: sanity(base, &c, own_bounds)
                .with_context(|| format!("sanity runs of {}", c.label))?,
            half_turns: summarise(&half, nominal),
            campaign: summarise(&campaign, nominal),
            chattering: chattering(base, &c, seed, own_bounds)?,
            bounds: own_bounds,
            contestant: c,
        });
        campaigns.push(campaign);
    }
    Ok((
        CompareReport {
            runs,
            seed,
            chattering_noise_deg: CHATTER_NOISE_DEG,
            plant: base.simulation.plant,
            definitions: convergence_of(base).describe(),
            bounds,
            results,
        },
        campaigns,
    ))
}

fn pct(part: u64, whole: u64) -> String {
    if whole == 0 {
        "-".into()
    } else {
        format!("{:.2} %", 100.0 * part as f64 / whole as f64)
    }
}

/// The markdown report.
pub fn markdown(r: &CompareReport, plots: &[(String, String)]) -> String {
    let b = &r.bounds;
    let tau_limit = b
        .limit_torque_Nm
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min);
    let mut md = String::new();
    let mut failures: Vec<String> = Vec::new();
    let _ = writeln!(md, "# The paper's law against the baselines\n");
    let _ = writeln!(
        md,
        "Same initial conditions and noise draws for every controller (seed {}). {} \
         Physical limits: T <= {} N, |tau_i| <= {} N m; the paper's a-priori bounds: T in [{:.2}, {:.2}] N, \
         |tau| <= ({:.3}, {:.3}, {:.3}) N m. Peaks are of the commands before clipping.\n",
        r.seed,
        r.definitions,
        b.limit_thrust_N,
        tau_limit,
        b.thrust_min_N,
        b.thrust_max_N,
        b.torque_max_Nm[0],
        b.torque_max_Nm[1],
        b.torque_max_Nm[2]
    );
    if let Some(without) = r
        .results
        .iter()
        .find(|c| c.contestant.controller == ControllerKind::Paper && !c.contestant.integral)
        .filter(|_| r.results.iter().any(|c| c.contestant.integral))
    {
        let w = &without.bounds;
        let _ = writeln!(
            md,
            "The scenario carries the bounded integral action (docs/integral-action.md): the bounds \
             above are its extended certificate's, which \"paper + integral\" is checked against. \
             \"paper\" flies the same scenario without `[gains.integral]` and is checked against \
             the paper's bounds of the same gains: T in [{:.2}, {:.2}] N, |tau| <= ({:.3}, {:.3}, \
             {:.3}) N m.\n",
            w.thrust_min_N, w.thrust_max_N, w.torque_max_Nm[0], w.torque_max_Nm[1], w.torque_max_Nm[2]
        );
    }
    let _ = writeln!(
        md,
        "## Sanity checks of each controller on its own (hover at (0, 0, 5) m, 10 s)\n"
    );
    let _ = writeln!(md, "| controller | hover: error at 10 s [m] | 1 m step: settling [s] | 1 m step: error at 10 s [m] | 30 deg roll: settling [s] |");
    let _ = writeln!(md, "| --- | --- | --- | --- | --- |");
    for c in &r.results {
        let s = &c.sanity;
        let _ = writeln!(
            md,
            "| {} | {:.2e} | {} | {:.2e} | {} |",
            s.label,
            s.hover_final_position_error_m,
            fmt_opt(s.step_settling_time_s),
            s.step_final_position_error_m,
            fmt_opt(s.tilt_settling_time_s)
        );
    }
    let _ = writeln!(
        md,
        "\n## Convergence from 180 deg (seven axes, position offset in a 10 m ball)\n"
    );
    let _ = writeln!(md, "| controller | converged | settling median / max [s] | time to < 90 deg median / max [s] | max switches in 1 s |");
    let _ = writeln!(md, "| --- | --- | --- | --- | --- |");
    for c in &r.results {
        let h = &c.half_turns;
        let _ = writeln!(
            md,
            "| {} | {}/{} | {} / {} | {} / {} | {} |",
            c.contestant.label,
            h.converged,
            h.runs,
            fmt_opt(h.settling_time_s.p50),
            fmt_opt(h.settling_time_s.max),
            fmt_opt(h.attitude_below_90deg_s.p50),
            fmt_opt(h.attitude_below_90deg_s.max),
            h.switching.max_switches_in_1s
        );
    }
    let _ = writeln!(md, "\n## Campaign: {} runs (the seven 180 deg starts, then Haar attitudes; offsets in balls of 10 m, 2 m/s, 2 rad/s)\n", r.runs);
    let _ = writeln!(md, "| controller | converged | settling p50 / p90 [s] | steady-state error p50 [m] | final attitude error p50 [deg] | peak T / T_max, median run / worst run | peak \\|tau_i\\| / tau_max, median run / worst run | samples beyond limits | samples outside a-priori bounds |");
    let _ = writeln!(
        md,
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"
    );
    for c in &r.results {
        let s = &c.campaign;
        let n = &s.nominal;
        let counts = if n.runs > 0 { n } else { &s.perturbed };
        let ratio = |x: Option<f64>, limit: f64| {
            x.map_or_else(|| "-".into(), |v| format!("{:.3}", v / limit))
        };
        if s.failed_runs > 0 {
            failures.push(format!(
                "{}: {} of {} runs stopped (controller undefined: F = 0 or b3d parallel to b1d).",
                c.contestant.label, s.failed_runs, s.runs
            ));
        }
        let a_priori = if c.contestant.controller == ControllerKind::Paper {
            format!("{} of {}", counts.samples_outside_a_priori, counts.samples)
        } else {
            "n/a".into()
        };
        let _ = writeln!(
            md,
            "| {} | {:.1} % ({}/{}) | {} / {} | {} | {} | {} / {} | {} / {} | {} ({}) | {} |",
            c.contestant.label,
            100.0 * s.fraction_converged,
            s.converged,
            s.runs,
            fmt_opt(s.settling_time_s.p50),
            fmt_opt(s.settling_time_s.p90),
            fmt_sci(s.steady_position_error_m.p50),
            fmt_sci(s.final_attitude_error_deg.p50),
            ratio(s.peak_thrust_N.p50, b.limit_thrust_N),
            ratio(s.peak_thrust_N.max, b.limit_thrust_N),
            ratio(s.peak_torque_Nm.p50, tau_limit),
            ratio(s.peak_torque_Nm.max, tau_limit),
            counts.samples_beyond_limits,
            pct(counts.samples_beyond_limits, counts.samples),
            a_priori
        );
    }
    if !r.plant.is_ideal() {
        let _ = writeln!(
            md,
            "\nOn the {} plant, what the firmware's mixer gave up in the campaign (commands the \
             rotors cannot realise):\n",
            r.plant.name()
        );
        let _ = writeln!(md, "| controller | samples given up | largest thrust given up [N] | largest torque given up [N m] |");
        let _ = writeln!(md, "| --- | --- | --- | --- |");
        for c in &r.results {
            if let Some(m) = &c.campaign.mixer {
                let m = if m.nominal.samples > 0 {
                    &m.nominal
                } else {
                    &m.perturbed
                };
                let _ = writeln!(
                    md,
                    "| {} | {} of {} ({}) | {:.3} | {:.4} |",
                    c.contestant.label,
                    m.samples_given_up,
                    m.samples,
                    pct(m.samples_given_up, m.samples),
                    m.thrust_given_up_max_N,
                    m.torque_given_up_max_Nm
                );
            }
        }
    }
    if !failures.is_empty() {
        let _ = writeln!(
            md,
            "\nRuns that stopped count as not converged. {}",
            failures.join(" ")
        );
    }
    let _ = writeln!(
        md,
        "\n## Chattering under attitude noise ({} deg per axis) at 180 deg (seven axes x 2 seeds, at the reference)\n",
        r.chattering_noise_deg
    );
    let _ = writeln!(md, "| controller | switches per run median / max | max switches in 1 s | time to < 90 deg median / max [s] | converged |");
    let _ = writeln!(md, "| --- | --- | --- | --- | --- |");
    for c in &r.results {
        let s = &c.chattering;
        let _ = writeln!(
            md,
            "| {} | {} / {} | {} | {} / {} | {}/{} |",
            c.contestant.label,
            fmt_opt(s.switching.switches_per_run.p50),
            fmt_opt(s.switching.switches_per_run.max),
            s.switching.max_switches_in_1s,
            fmt_opt(s.attitude_below_90deg_s.p50),
            fmt_opt(s.attitude_below_90deg_s.max),
            s.converged,
            s.runs
        );
    }
    let _ = writeln!(md, "\nLee et al.'s law has no switching (a continuous attitude error); at exactly 180 deg its e_R vanishes, so it leaves only through noise or the translational coupling.\n");
    for (title, file) in plots {
        let _ = writeln!(md, "![{title}]({file})\n");
    }
    md
}

fn fmt_sci(x: Option<f64>) -> String {
    x.map_or_else(|| "-".into(), |v| format!("{v:.2e}"))
}

fn write_plots(
    dir: &Path,
    base: &Scenario,
    report: &CompareReport,
    campaigns: &[Vec<RunResult>],
) -> Result<Vec<(String, String)>> {
    let mut files = Vec::new();
    let mut traces = Vec::new();
    for c in &report.results {
        let s = c.contestant.scenario(base);
        let (_, points) = trace(
            &s,
            c.contestant.controller,
            &s.initial_state(),
            0,
            convergence_of(base),
            c.bounds,
        )?;
        traces.push((c.contestant.label.clone(), points));
    }
    let fields: [crate::runs::trace::PanelSpec; 3] = [
        (
            "compare_position_error.png",
            "Position error from the paper's start",
            "|p - p_d| [m]",
            Scale::Log,
            |p| p.position_error_m,
        ),
        (
            "compare_attitude_error.png",
            "Attitude error from the paper's start",
            "angle(R_d^T R) [deg]",
            Scale::Log,
            |p| p.attitude_error_deg,
        ),
        (
            "compare_torque.png",
            "Largest torque component from the paper's start",
            "max_i |tau_i| [N m]",
            Scale::Log,
            |p| p.torque_abs_max_Nm,
        ),
    ];
    for (file, title, y_label, scale, f) in fields {
        let mut series: Vec<Series> = traces
            .iter()
            .enumerate()
            .map(|(i, (label, pts))| {
                Series::line(
                    label,
                    PALETTE[i],
                    pts.iter().map(|p| (p.t_s, f(p))).collect(),
                )
            })
            .collect();
        if file == "compare_torque.png" {
            let span = 0.0..base.simulation.duration_s;
            series.push(Series::level(
                Some("limit"),
                PALETTE[5],
                report.bounds.limit_torque_Nm[0],
                &span,
            ));
        }
        time_series_png(
            &dir.join(file),
            &Panel {
                file,
                title: title.into(),
                y_label: y_label.into(),
                scale,
                series,
                legend_at: LegendAt::LowerLeft,
            },
        )?;
        files.push((title.to_string(), file.to_string()));
    }
    let file = "compare_settling_cdf.png";
    let series: Vec<XySeries> = report
        .results
        .iter()
        .zip(campaigns)
        .enumerate()
        .map(|(i, (c, runs))| {
            let settling: Vec<f64> = runs
                .iter()
                .filter_map(|r| r.metrics.as_ref().and_then(|m| m.settling_time_s))
                .collect();
            XySeries {
                label: c.contestant.label.clone(),
                color: PALETTE[i],
                style: Style::Line,
                points: cdf_points(&settling, runs.len(), base.simulation.duration_s),
            }
        })
        .collect();
    xy_figure(
        &dir.join(file),
        &format!("Fraction of the {} campaign runs settled by t", report.runs),
        &Axis::linear("t [s]"),
        &Axis::linear("fraction of runs"),
        &series,
    )?;
    files.push(("Settling-time CDF".into(), file.into()));
    Ok(files)
}

/// What the `compare` job runs (the command line's defaults in parentheses).
#[derive(Clone, Debug, PartialEq)]
pub struct CompareOptions {
    /// Output directory, created; files overwritten (`out/compare`).
    pub out: PathBuf,
    /// Runs of the campaign each controller flies, the same initial conditions for all (200).
    pub runs: u64,
    /// Scenario, seed and overrides.
    pub base: BaseOptions,
}

/// `host-sim compare`: runs the comparison and writes `compare.md`, `compare.json`, plots.
///
/// Errors: invalid scenario, a failed sanity run, or a file that cannot be written.
pub fn run_command(args: &CompareOptions) -> Result<()> {
    let base = args.base.scenario()?;
    let (report, campaigns) = run_compare(&base, args.runs, args.base.seed)?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let plots = write_plots(&args.out, &base, &report, &campaigns)?;
    let md = markdown(&report, &plots);
    let md_path = args.out.join("compare.md");
    std::fs::write(&md_path, &md).with_context(|| format!("writing {}", md_path.display()))?;
    let json_path = args.out.join("compare.json");
    std::fs::write(&json_path, serde_json::to_string_pretty(&report)? + "\n")
        .with_context(|| format!("writing {}", json_path.display()))?;
    print!("{md}");
    println!(
        "Wrote compare.md, compare.json and {} plots to {}",
        plots.len(),
        args.out.display()
    );
    Ok(())
}
