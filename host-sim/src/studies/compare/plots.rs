//! The comparison's figures.

use super::CompareReport;
use crate::model::scenario::Scenario;
use crate::output::chart::{LegendAt, Panel, Scale, Series};
use crate::runs::runner::RunResult;
use crate::runs::trace::trace;
use crate::studies::ablation::integral::convergence_of;
use crate::studies::campaign::figures::{
    cdf_points, time_series_png, xy_figure, Axis, Style, XySeries, PALETTE,
};
use anyhow::Result;
use std::path::Path;

pub(super) fn write_plots(
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
