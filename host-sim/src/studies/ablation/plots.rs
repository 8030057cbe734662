//! The ablation's figures.

use super::{AblationReport, Traces};
use crate::output::chart::{LegendAt, Panel, Scale, Series};
use crate::studies::campaign::figures::{
    time_series_png, xy_figure, Axis, Style, XySeries, PALETTE,
};
use anyhow::Result;
use std::path::Path;

pub(super) fn write_plots(
    dir: &Path,
    report: &AblationReport,
    traces: &Traces,
) -> Result<Vec<(String, String)>> {
    let mut files = Vec::new();
    let span = traces
        .first()
        .and_then(|t| t.2.last())
        .map_or(0.0..1.0, |p| 0.0..p.t_s);
    let panels: [crate::runs::trace::PanelSpec; 3] = [
        (
            "filters_omega_d.png",
            "|omega_d|, filtered vs unfiltered (paper start)",
            "|omega_d| [rad/s]",
            Scale::Log,
            |p| p.omega_d_rad_s,
        ),
        (
            "filters_omega_d_dot.png",
            "|omega_d_dot|, filtered vs unfiltered (paper start)",
            "|omega_d_dot| [rad/s^2]",
            Scale::Log,
            |p| p.omega_d_dot_rad_s2,
        ),
        (
            "filters_torque.png",
            "max_i |tau_i|, filtered vs unfiltered (paper start)",
            "torque [N m]",
            Scale::Log,
            |p| p.torque_abs_max_Nm,
        ),
    ];
    for (file, title, y_label, scale, f) in panels {
        let mut series: Vec<Series> = traces
            .iter()
            .enumerate()
            .map(|(i, (_, law, pts))| {
                Series::line(
                    law.label(),
                    PALETTE[i],
                    pts.iter().map(|p| (p.t_s, f(p))).collect(),
                )
            })
            .collect();
        if file == "filters_torque.png" {
            let lowest = report
                .bounds
                .torque_max_Nm
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min);
            series.push(Series::level(
                Some("smallest a-priori torque bound"),
                PALETTE[5],
                lowest,
                &span,
            ));
        }
        let panel = Panel {
            file,
            title: title.into(),
            y_label: y_label.into(),
            scale,
            series,
            legend_at: LegendAt::UpperRight,
        };
        time_series_png(&dir.join(file), &panel)?;
        files.push((title.to_string(), file.to_string()));
    }
    let file = "hysteresis_switches.png";
    let mut series: Vec<XySeries> = Vec::new();
    for r in &report.hysteresis {
        // +1 so that zero switches shows on the log axis.
        let point = (
            r.attitude_noise_deg,
            r.switches_per_run.max.unwrap_or(0.0) + 1.0,
        );
        match series.iter_mut().find(|s| s.label == r.lifting) {
            Some(s) => s.points.push(point),
            None => series.push(XySeries {
                label: r.lifting.clone(),
                color: PALETTE[series.len()],
                style: Style::Line,
                points: vec![point],
            }),
        }
    }
    xy_figure(
        &dir.join(file),
        "Most switches in one 180-deg run vs attitude noise",
        &Axis::linear("attitude noise std [deg]"),
        &Axis::log("(switches per run + 1)"),
        &series,
    )?;
    files.push(("Switches vs noise".into(), file.into()));
    let file = "no_dive_altitude.png";
    let r = &report.no_dive_thrust;
    let panel = Panel {
        file,
        title: "Altitude from the paper's start: T = m|u| vs no-dive thrust".into(),
        y_label: "z [m]".into(),
        scale: Scale::Linear,
        series: r
            .altitude_traces
            .iter()
            .enumerate()
            .map(|(i, (label, points))| Series::line(label, PALETTE[i], points.clone()))
            .collect(),
        legend_at: LegendAt::LowerRight,
    };
    time_series_png(&dir.join(file), &panel)?;
    files.push(("Altitude, no-dive thrust".into(), file.into()));
    Ok(files)
}
