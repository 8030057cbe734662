//! The integral-action ablation's report: one row per case and law, the gains flown, and its
//! Markdown page.

use crate::output::fmt_opt;
use crate::output::markdown_table::{Rule, Table};
use crate::runs::metrics::BoundSet;
use crate::runs::sampler::HALF_TURN_AXES;
use crate::runs::stats::Distribution;
use std::fmt::Write as _;

use serde::Serialize;

/// One cell: a case flown with or without the integral action.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct IntegralRow {
    /// The case's label ([`super::Case::name`]).
    pub case: String,
    /// Integral action on.
    pub integral: bool,
    /// Runs flown.
    pub runs: usize,
    /// Runs the law refused (a non-finite sample); counted as not converged.
    pub refused: usize,
    /// Runs converged ([`super::convergence_of`] the scenario).
    pub converged: usize,
    /// `100 converged / runs`.
    pub converged_percent: f64,
    /// Steady position error (mean `|p − p_d|` over the last 5 s) \[mm\], converged runs.
    pub steady_error_converged_mm: Distribution,
    /// Steady position error \[mm\], every run that finished.
    pub steady_error_all_mm: Distribution,
    /// Samples outside the a-priori bounds of the gains flown, over all runs.
    pub samples_outside_a_priori: u64,
    /// Samples above the tight bounds of the gains flown, over all runs (`None`: not checked,
    /// the integral gains are not the scenario's own).
    pub samples_above_tight: Option<u64>,
    /// The seven 180° starts: time until the attitude error is first below 90° \[s\].
    pub half_turn_time_to_90deg_s: Distribution,
    /// The seven 180° starts: settling time \[s\] (of those that settled).
    pub half_turn_settling_s: Distribution,
    /// The seven 180° starts that settled.
    pub half_turn_settled: usize,
}

/// The integral gains flown, for the report (SI units in the names).
#[derive(Clone, Copy, Debug, Serialize, PartialEq)]
#[allow(non_snake_case)]
pub struct IntegralGainsReport {
    /// `k_i` [1/s³].
    pub k_i: f64,
    /// `M_i` per inertial axis [m/s²].
    pub M_i_m_s2: [f64; 3],
    /// `R_i` per inertial axis [m/s³].
    pub R_i_m_s3: [f64; 3],
    /// `k_η` [1/s].
    pub k_eta: f64,
}

/// `ablation.json`'s `integral_action`.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct IntegralReport {
    /// Definitions of the measured quantities.
    pub definitions: String,
    /// The integral gains flown.
    pub gains: IntegralGainsReport,
    /// `"scenario"` (its `gains.integral`) or `"default"` ([`super::default_integral_gains`]).
    pub gains_source: String,
    /// Bounds checked without the integral action (the paper's).
    pub bounds_without: BoundSet,
    /// Bounds checked with it (the extended certificate's).
    pub bounds_with: BoundSet,
    /// Whether every condition of the extended certificate holds.
    pub extended_certificate_holds: bool,
    /// The violated conditions of the extended certificate, `"name: lhs vs rhs"`.
    pub extended_violations: Vec<String>,
    /// Every cell: per case, without then with.
    pub rows: Vec<IntegralRow>,
}

/// Appends the integral action's section of `ablation.md` to `md`.
pub fn markdown(md: &mut String, r: &IntegralReport) {
    let g = &r.gains;
    let b = &r.bounds_with;
    let _ = writeln!(md, "\n## Integral action: without vs with\n");
    let _ = writeln!(
        md,
        "Gains ({}): k_i = {} 1/s^3, M_i = ({:.3}, {:.3}, {:.3}) m/s^2, R_i = ({}, {}, {}) m/s^3, \
         k_eta = {} 1/s. Extended bounds: thrust in [{:.3}, {:.3}] N, torque per axis <= \
         ({:.3}, {:.3}, {:.3}) N m. Extended certificate: {}.\n",
        r.gains_source,
        g.k_i,
        g.M_i_m_s2[0],
        g.M_i_m_s2[1],
        g.M_i_m_s2[2],
        g.R_i_m_s3[0],
        g.R_i_m_s3[1],
        g.R_i_m_s3[2],
        g.k_eta,
        b.thrust_min_N,
        b.thrust_max_N,
        b.torque_max_Nm[0],
        b.torque_max_Nm[1],
        b.torque_max_Nm[2],
        if r.extended_certificate_holds {
            "every condition holds".to_string()
        } else {
            format!("violated: {}", r.extended_violations.join("; "))
        }
    );
    let _ = writeln!(md, "{}\n", r.definitions);
    let mut table = Table::new(
        md,
        &[
            "case",
            "integral",
            "runs",
            "steady error p50 / p99, converged [mm]",
            "steady error p50 / p99, all [mm]",
            "converged",
            "samples outside a-priori / above tight",
            "180-deg: time to < 90 deg p90 [s]",
            "180-deg: settling p90 [s] (settled)",
        ],
        Rule::Spaced,
    );
    let mm = |v: Option<f64>| v.map_or_else(|| "-".to_string(), |x| format!("{x:.3}"));
    for row in &r.rows {
        table.row(&[
            row.case.to_string(),
            if row.integral { "on" } else { "off" }.to_string(),
            row.runs.to_string(),
            format!(
                "{} / {}",
                mm(row.steady_error_converged_mm.p50),
                mm(row.steady_error_converged_mm.p99)
            ),
            format!(
                "{} / {}",
                mm(row.steady_error_all_mm.p50),
                mm(row.steady_error_all_mm.p99)
            ),
            format!("{:.1} %", row.converged_percent),
            format!(
                "{} / {}",
                row.samples_outside_a_priori,
                row.samples_above_tight
                    .map_or_else(|| "-".to_string(), |n| n.to_string())
            ),
            fmt_opt(row.half_turn_time_to_90deg_s.p90),
            format!(
                "{} ({}/{})",
                fmt_opt(row.half_turn_settling_s.p90),
                row.half_turn_settled,
                HALF_TURN_AXES.len().min(row.runs)
            ),
        ]);
    }
}
