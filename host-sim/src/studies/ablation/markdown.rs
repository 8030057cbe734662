//! The ablation's Markdown page: the hysteresis and filter tables and the no-dive section.

use super::AblationReport;
use crate::output::fmt_opt;
use crate::output::markdown_table::{Rule, Table};
use crate::studies::ablation::no_dive::NoDiveReport;
use std::fmt::Write as _;

/// The markdown report.
pub fn markdown(report: &AblationReport, plots: &[(String, String)]) -> String {
    let mut md = String::new();
    let _ = writeln!(md, "# Ablations of the paper's design choices\n");
    if !report.plant.is_ideal() {
        let _ = writeln!(
            md,
            "Every run flies the {} plant: the commands go through the firmware's mixer and the \
             rotors' motor dynamics.\n",
            report.plant.name()
        );
    }
    let _ = writeln!(
        md,
        "## Hysteresis: hybrid path lifting vs memoryless `q0 >= 0` lifting\n"
    );
    let _ = writeln!(
        md,
        "Seven starts exactly 180 deg from R_d(0) (axes x, y, z, xy, xz, yz, xyz), at the reference \
         position, repeated with different noise seeds; attitude measurement noise per axis.\n"
    );
    let mut table = Table::new(
        &mut md,
        &[
            "lifting",
            "attitude noise [deg]",
            "runs",
            "switches per run (median / max)",
            "max switches in 1 s",
            "time to < 90 deg, median / max [s]",
            "converged",
        ],
        Rule::Spaced,
    );
    for r in &report.hysteresis {
        table.row(&[
            r.lifting.to_string(),
            r.attitude_noise_deg.to_string(),
            r.runs.to_string(),
            format!(
                "{} / {}",
                fmt_opt(r.switches_per_run.p50),
                fmt_opt(r.switches_per_run.max)
            ),
            r.max_switches_in_1s.to_string(),
            format!(
                "{} / {}",
                fmt_opt(r.time_to_90deg_s.p50),
                fmt_opt(r.time_to_90deg_s.max)
            ),
            format!("{}/{}", r.converged, r.runs),
        ]);
    }
    let _ = writeln!(
        md,
        "\n## Filters: filtered outer loop vs unfiltered saturated law\n"
    );
    let b = &report.bounds;
    let _ = writeln!(
        md,
        "A-priori bounds (filtered law): |omega_d| <= U_wd, torque per axis <= ({:.3}, {:.3}, {:.3}) N m, thrust in [{:.3}, {:.3}] N.\n",
        b.torque_max_Nm[0], b.torque_max_Nm[1], b.torque_max_Nm[2], b.thrust_min_N, b.thrust_max_N
    );
    let mut table = Table::new(
        &mut md,
        &[
            "case",
            "law",
            "peak \\|omega_d\\| [rad/s]",
            "peak \\|omega_d_dot\\| [rad/s^2]",
            "peak \\|tau\\| x, y, z [N m]",
            "thrust range [N]",
            "samples outside a-priori",
            "samples beyond limits",
            "settling [s]",
        ],
        Rule::Spaced,
    );
    for r in &report.filters {
        table.row(&[
            r.case.to_string(),
            r.law.to_string(),
            format!("{:.3}", r.omega_d_max_rad_s),
            format!("{:.2}", r.omega_d_dot_max_rad_s2),
            format!(
                "{:.3}, {:.3}, {:.3}",
                r.torque_abs_max_Nm[0], r.torque_abs_max_Nm[1], r.torque_abs_max_Nm[2]
            ),
            format!("[{:.2}, {:.2}]", r.thrust_range_N[0], r.thrust_range_N[1]),
            r.samples_outside_a_priori.to_string(),
            r.samples_beyond_limits.to_string(),
            fmt_opt(r.settling_time_s),
        ]);
    }
    no_dive_markdown(&mut md, &report.no_dive_thrust);
    crate::studies::ablation::integral::markdown(&mut md, &report.integral_action);
    let _ = writeln!(md);
    for (title, file) in plots {
        let _ = writeln!(md, "![{title}]({file})\n");
    }
    md
}

pub(super) fn no_dive_markdown(md: &mut String, r: &NoDiveReport) {
    let _ = writeln!(
        md,
        "\n## No-dive thrust: T = m|u| vs {}\n",
        r.no_dive.thrust.name()
    );
    let _ = writeln!(
        md,
        "Certified thrust interval with the option: [{:.3}, {:.3}] N. Flip cost (paper start \
         minus upright start): {:.2} m with T = m|u|, {:.2} m with the option ({:.0} %).\n",
        r.no_dive_thrust_interval_N[0],
        r.no_dive_thrust_interval_N[1],
        r.flip_cost_norm_m,
        r.flip_cost_no_dive_m,
        100.0 * r.flip_cost_no_dive_m / r.flip_cost_norm_m
    );
    let mut table = Table::new(
        md,
        &[
            "start",
            "altitude lost, T = m\\|u\\| [m]",
            "altitude lost, no-dive [m]",
            "ratio",
            "settling, T = m\\|u\\| [s]",
            "settling, no-dive [s]",
        ],
        Rule::Spaced,
    );
    for a in &r.altitude {
        table.row(&[
            a.start.to_string(),
            format!("{:.2}", a.altitude_loss_norm_m),
            format!("{:.2}", a.altitude_loss_no_dive_m),
            format!("{:.2}", a.altitude_loss_no_dive_m / a.altitude_loss_norm_m),
            fmt_opt(a.settling_norm_s),
            fmt_opt(a.settling_no_dive_s),
        ]);
    }
    let _ = writeln!(
        md,
        "\nChattering: the seven 180-deg starts at hover under attitude measurement noise.\n"
    );
    let mut table = Table::new(
        md,
        &[
            "thrust",
            "attitude noise [deg]",
            "runs",
            "MRP switches per s (mean)",
            "max switches in 1 s",
            "thrust cut-offs per s (mean)",
            "max cut-offs in 1 s",
            "converged",
        ],
        Rule::Spaced,
    );
    for c in &r.chattering {
        table.row(&[
            c.thrust.to_string(),
            c.attitude_noise_deg.to_string(),
            c.runs.to_string(),
            format!("{:.3}", c.switches_per_s),
            c.max_switches_in_1s.to_string(),
            format!("{:.3}", c.thrust_cutoffs_per_s),
            c.max_thrust_cutoffs_in_1s.to_string(),
            format!("{}/{}", c.converged, c.runs),
        ]);
    }
}
