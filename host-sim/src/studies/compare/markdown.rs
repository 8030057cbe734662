//! The comparison's Markdown page: per-contestant tables of the nominal tasks, the campaigns and
//! the sanity checks.

use super::CompareReport;
use crate::fly::controllers::ControllerKind;
use crate::output::fmt_opt;
use crate::output::markdown_table::{Rule, Table};
use std::fmt::Write as _;

pub(super) fn pct(part: u64, whole: u64) -> String {
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
        "## Sanity checks of each controller on its own (hover at (0, 0, 5) m, 10 s; the \
         scenario's own reference from its initial state)\n"
    );
    let mut t = Table::new(
        &mut md,
        &[
            "controller",
            "hover: error at 10 s [m]",
            "1 m step: settling [s]",
            "1 m step: error at 10 s [m]",
            "30 deg roll: settling [s]",
            "reference: mean error over the last 5 s [m]",
        ],
        Rule::Spaced,
    );
    for c in &r.results {
        let s = &c.sanity;
        t.row(&[
            s.label.clone(),
            format!("{:.2e}", s.hover_final_position_error_m),
            fmt_opt(s.step_settling_time_s),
            format!("{:.2e}", s.step_final_position_error_m),
            fmt_opt(s.tilt_settling_time_s),
            s.helix_tracking_error_m
                .map_or("–".to_owned(), |e| format!("{e:.2e}")),
        ]);
    }
    let _ = writeln!(
        md,
        "\n## Convergence from 180 deg (seven axes, position offset in a 10 m ball)\n"
    );
    let mut t = Table::new(
        &mut md,
        &[
            "controller",
            "converged",
            "settling median / max [s]",
            "time to < 90 deg median / max [s]",
            "max switches in 1 s",
        ],
        Rule::Spaced,
    );
    for c in &r.results {
        let h = &c.half_turns;
        t.row(&[
            c.contestant.label.clone(),
            format!("{}/{}", h.converged, h.runs),
            format!(
                "{} / {}",
                fmt_opt(h.settling_time_s.p50),
                fmt_opt(h.settling_time_s.max)
            ),
            format!(
                "{} / {}",
                fmt_opt(h.attitude_below_90deg_s.p50),
                fmt_opt(h.attitude_below_90deg_s.max)
            ),
            h.switching.max_switches_in_1s.to_string(),
        ]);
    }
    let _ = writeln!(md, "\n## Campaign: {} runs (the seven 180 deg starts, then Haar attitudes; offsets in balls of 10 m, 2 m/s, 2 rad/s)\n", r.runs);
    let mut t = Table::new(
        &mut md,
        &[
            "controller",
            "converged",
            "settling p50 / p90 [s]",
            "steady-state error p50 [m]",
            "final attitude error p50 [deg]",
            "peak T / T_max, median run / worst run",
            "peak \\|tau_i\\| / tau_max, median run / worst run",
            "samples beyond limits",
            "samples outside a-priori bounds",
        ],
        Rule::Spaced,
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
        t.row(&[
            c.contestant.label.clone(),
            format!(
                "{:.1} % ({}/{})",
                100.0 * s.fraction_converged,
                s.converged,
                s.runs
            ),
            format!(
                "{} / {}",
                fmt_opt(s.settling_time_s.p50),
                fmt_opt(s.settling_time_s.p90)
            ),
            fmt_sci(s.steady_position_error_m.p50),
            fmt_sci(s.final_attitude_error_deg.p50),
            format!(
                "{} / {}",
                ratio(s.peak_thrust_N.p50, b.limit_thrust_N),
                ratio(s.peak_thrust_N.max, b.limit_thrust_N)
            ),
            format!(
                "{} / {}",
                ratio(s.peak_torque_Nm.p50, tau_limit),
                ratio(s.peak_torque_Nm.max, tau_limit)
            ),
            format!(
                "{} ({})",
                counts.samples_beyond_limits,
                pct(counts.samples_beyond_limits, counts.samples)
            ),
            a_priori,
        ]);
    }
    if !r.plant.is_ideal() {
        let _ = writeln!(
            md,
            "\nOn the {} plant, what the firmware's mixer gave up in the campaign (commands the \
             rotors cannot realise):\n",
            r.plant.name()
        );
        let mut t = Table::new(
            &mut md,
            &[
                "controller",
                "samples given up",
                "largest thrust given up [N]",
                "largest torque given up [N m]",
            ],
            Rule::Spaced,
        );
        for c in &r.results {
            if let Some(m) = &c.campaign.mixer {
                let m = if m.nominal.samples > 0 {
                    &m.nominal
                } else {
                    &m.perturbed
                };
                t.row(&[
                    c.contestant.label.clone(),
                    format!(
                        "{} of {} ({})",
                        m.samples_given_up,
                        m.samples,
                        pct(m.samples_given_up, m.samples)
                    ),
                    format!("{:.3}", m.thrust_given_up_max_N),
                    format!("{:.4}", m.torque_given_up_max_Nm),
                ]);
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
    let mut t = Table::new(
        &mut md,
        &[
            "controller",
            "switches per run median / max",
            "max switches in 1 s",
            "time to < 90 deg median / max [s]",
            "converged",
        ],
        Rule::Spaced,
    );
    for c in &r.results {
        let s = &c.chattering;
        t.row(&[
            c.contestant.label.clone(),
            format!(
                "{} / {}",
                fmt_opt(s.switching.switches_per_run.p50),
                fmt_opt(s.switching.switches_per_run.max)
            ),
            s.switching.max_switches_in_1s.to_string(),
            format!(
                "{} / {}",
                fmt_opt(s.attitude_below_90deg_s.p50),
                fmt_opt(s.attitude_below_90deg_s.max)
            ),
            format!("{}/{}", s.converged, s.runs),
        ]);
    }
    let _ = writeln!(md, "\nLee et al.'s law has no switching (a continuous attitude error); at exactly 180 deg its e_R vanishes, so it leaves only through noise or the translational coupling.\n");
    for (title, file) in plots {
        let _ = writeln!(md, "![{title}]({file})\n");
    }
    md
}

pub(super) fn fmt_sci(x: Option<f64>) -> String {
    x.map_or_else(|| "-".into(), |v| format!("{v:.2e}"))
}
