//! The eight panels of the paper's Section VI (Figs. 1a–d and 2a–d), one PNG each, plus
//! `overview.png` with all eight in a 4 × 2 grid.

use std::f64::consts::PI;
use std::ops::Range;
use std::path::{Path, PathBuf};

use anyhow::Result;
use plotters::prelude::*;

use crate::fly::sim::{Record, Summary};
use crate::model::scenario::Scenario;
use crate::output::chart::{self, Panel, Points, Scale, Series};
use crate::output::png::{ensure_font, write_png};

/// File name of the combined figure.
pub const OVERVIEW_FILE: &str = "overview.png";
/// The torque against both a-priori bounds (written after [`OVERVIEW_FILE`], not in it).
pub const BOUNDS_FILE: &str = "bounds.png";

/// Size of each single-panel PNG \[px\].
const PANEL_SIZE: (u32, u32) = (900, 520);
/// Size of [`OVERVIEW_FILE`] \[px\]: 4 rows × 2 columns of 700 × 450 cells.
const OVERVIEW_SIZE: (u32, u32) = (1400, 1800);
const OVERVIEW_GRID: (usize, usize) = (4, 2);

// A colour-blind-friendly palette that survives greyscale printing reasonably.
const C_X: RGBColor = RGBColor(31, 119, 180);
const C_Y: RGBColor = RGBColor(230, 120, 0);
const C_Z: RGBColor = RGBColor(44, 160, 44);
const C_BOUND: RGBColor = RGBColor(214, 39, 40);
const C_LIMIT: RGBColor = RGBColor(80, 80, 80);
const AXES: [(&str, RGBColor); 3] = [("x", C_X), ("y", C_Y), ("z", C_Z)];

/// Writes the eight panel PNGs (`position.png`, `yaw.png`, `position_error.png`,
/// `mrp_error.png`, `thrust.png`, `torque.png`, `filters.png`, `saturations.png`),
/// [`OVERVIEW_FILE`] and [`BOUNDS_FILE`] into `dir`, which must exist. Bounds come from `summary.a_priori`
/// (Theorems 1–2), actuator limits and saturation levels from `scenario`.
///
/// Returns the paths written, in that order. Log-scale panels clamp values below
/// 1e-12 (e.g. exact zeros) to it.
///
/// Errors: the embedded font is refused, or a PNG cannot be drawn or written (the error names
/// the file).
pub fn write_plots(
    dir: &Path,
    scenario: &Scenario,
    summary: &Summary,
    records: &[Record],
) -> Result<Vec<PathBuf>> {
    ensure_font()?;
    let panels = panels(scenario, summary, records);
    let mut written = Vec::with_capacity(panels.len() + 1);
    for panel in &panels {
        let path = dir.join(panel.file);
        write_png(&path, PANEL_SIZE, |root| chart::draw(root, panel))?;
        written.push(path);
    }
    let path = dir.join(OVERVIEW_FILE);
    write_png(&path, OVERVIEW_SIZE, |root| {
        for (cell, panel) in root.split_evenly(OVERVIEW_GRID).iter().zip(&panels) {
            chart::draw(cell, panel)?;
        }
        Ok(())
    })?;
    written.push(path);
    // Not in the overview grid, which keeps the paper's Fig. 2 layout.
    let bounds = bounds_panel(summary, records);
    let path = dir.join(bounds.file);
    write_png(&path, PANEL_SIZE, |root| chart::draw(root, &bounds))?;
    written.push(path);
    Ok(written)
}

/// Reads one column of a [`Record`].
type Field = fn(&Record) -> f64;

/// `(t, f(record))` for every record.
fn column(records: &[Record], f: impl Fn(&Record) -> f64) -> Points {
    records.iter().map(|r| (r.t_s, f(r))).collect()
}

/// The run's time span \[s\] (for the horizontal bound lines).
fn time_span(records: &[Record]) -> Range<f64> {
    match (records.first(), records.last()) {
        (Some(a), Some(b)) => a.t_s..b.t_s,
        _ => 0.0..1.0,
    }
}

/// Wraps an angle into `(-π, π]` \[rad\].
fn wrap_pi(a: f64) -> f64 {
    let w = a.rem_euclid(2.0 * PI);
    if w > PI {
        w - 2.0 * PI
    } else {
        w
    }
}

/// Removes the ±2π jumps of a wrapped angle \[rad\] so it plots as a continuous curve.
fn unwrap(angles: impl Iterator<Item = f64>) -> Vec<f64> {
    let mut out: Vec<f64> = Vec::new();
    for a in angles {
        let next = match out.last() {
            Some(&prev) => prev + wrap_pi(a - prev),
            None => a,
        };
        out.push(next);
    }
    out
}

/// Yaw and desired yaw \[rad\], both unwrapped. Both are only known modulo 2π, and ψ_d = π sin(f t)
/// touches ±π, so the wrapped values jump across the whole axis. The vehicle's yaw is shifted
/// by the multiple of 2π that makes it end within π of ψ_d, so converged tracking overlaps.
fn yaw_series(records: &[Record]) -> (Points, Points) {
    let reference = unwrap(records.iter().map(|r| r.yaw_ref_rad));
    let mut yaw = unwrap(records.iter().map(|r| r.yaw_rad));
    if let (Some(&y), Some(&d)) = (yaw.last(), reference.last()) {
        let shift = d + wrap_pi(y - d) - y;
        yaw.iter_mut().for_each(|v| *v += shift);
    }
    let with_t = |v: Vec<f64>| -> Points { records.iter().map(|r| r.t_s).zip(v).collect() };
    (with_t(yaw), with_t(reference))
}

/// The eight panels, in the paper's order.
fn panels(scenario: &Scenario, summary: &Summary, records: &[Record]) -> Vec<Panel> {
    let span = time_span(records);
    vec![
        position_panel(records),
        yaw_panel(records),
        error_panel(
            "position_error.png",
            "Position error norm",
            "|p − p_d| [m]",
            ("|p − p_d|", column(records, |r| r.position_error_m)),
            (1e-3, "1 mm"),
            &span,
        ),
        error_panel(
            "mrp_error.png",
            "MRP error norm",
            "|MRP error| [–]",
            ("|MRP error|", column(records, |r| r.mrp_error)),
            (1e-4, "1e-4"),
            &span,
        ),
        thrust_panel(scenario, summary, records, &span),
        torque_panel(scenario, summary, records, &span),
        filters_panel(scenario, records, &span),
        saturations_panel(scenario, records, &span),
    ]
}

/// Defaults shared by every panel: linear y, legend top right.
fn panel(file: &'static str, title: &str, y_label: &str, series: Vec<Series>) -> Panel {
    Panel {
        file,
        title: title.to_owned(),
        y_label: y_label.to_owned(),
        scale: Scale::Linear,
        series,
        legend_at: SeriesLabelPosition::UpperRight,
    }
}

/// Fig. 1a: x, y, z (solid) and their references (dashed, same colour).
fn position_panel(records: &[Record]) -> Panel {
    let pick: [(Field, Field); 3] = [
        (|r| r.x_m, |r| r.x_ref_m),
        (|r| r.y_m, |r| r.y_ref_m),
        (|r| r.z_m, |r| r.z_ref_m),
    ];
    let series = AXES
        .iter()
        .zip(pick)
        .flat_map(|(&(axis, color), (actual, reference))| {
            [
                Series::line(axis, color, column(records, actual)),
                Series::dashed(&format!("{axis}_d"), color, column(records, reference)),
            ]
        })
        .collect();
    // Bottom right: after the transient the paper's trajectory stays in the upper half.
    Panel {
        legend_at: SeriesLabelPosition::LowerRight,
        ..panel(
            "position.png",
            "Position vs reference",
            "position [m]",
            series,
        )
    }
}

/// Fig. 1b: yaw and desired yaw, unwrapped (see [`yaw_series`]).
fn yaw_panel(records: &[Record]) -> Panel {
    let (yaw, reference) = yaw_series(records);
    let series = vec![
        Series::line("ψ", C_X, yaw),
        Series::dashed("ψ_d", C_BOUND, reference),
    ];
    panel("yaw.png", "Yaw vs desired yaw", "yaw [rad]", series)
}

/// Figs. 1c–d: an error norm on a log axis with its settling threshold.
fn error_panel(
    file: &'static str,
    title: &str,
    y_label: &str,
    (label, points): (&str, Points),
    (threshold, threshold_label): (f64, &str),
    span: &Range<f64>,
) -> Panel {
    let series = vec![
        Series::line(label, C_X, points),
        Series::level(Some(threshold_label), C_BOUND, threshold, span),
    ];
    Panel {
        scale: Scale::Log,
        ..panel(file, title, y_label, series)
    }
}

/// Fig. 2a: thrust with the a-priori interval (`[T_min, T_max]`, or `[T_floor, T_max]` with the
/// no-dive thrust) and the actuator limit.
fn thrust_panel(
    scenario: &Scenario,
    summary: &Summary,
    records: &[Record],
    span: &Range<f64>,
) -> Panel {
    let b = &summary.a_priori;
    // With the no-dive thrust the certified interval is [T_floor, T_max], not Theorem 1's.
    let (label, [low, high]) = match b.no_dive_thrust_interval_N {
        Some(interval) => ("T_floor, T_max (a priori)", interval),
        None => ("T_min, T_max (a priori)", [b.thrust_min_N, b.thrust_max_N]),
    };
    let series = vec![
        Series::line("T", C_X, column(records, |r| r.thrust_N)),
        Series::level(Some(label), C_BOUND, low, span),
        Series::level(None, C_BOUND, high, span),
        Series::level(
            Some("actuator limit"),
            C_LIMIT,
            scenario.limits.thrust_max_N,
            span,
        ),
    ];
    // Middle right: late in the run the thrust settles near hover, below the box, and the
    // bound lines above and below it stay whole.
    Panel {
        legend_at: SeriesLabelPosition::MiddleRight,
        ..panel("thrust.png", "Thrust", "thrust [N]", series)
    }
}

/// Fig. 2b: torque per axis, ± its a-priori bound (dashed, same colour) and ± the actuator
/// limit (grey; one pair per distinct limit value).
fn torque_panel(
    scenario: &Scenario,
    summary: &Summary,
    records: &[Record],
    span: &Range<f64>,
) -> Panel {
    let pick: [Field; 3] = [|r| r.torque_x_Nm, |r| r.torque_y_Nm, |r| r.torque_z_Nm];
    let mut series: Vec<Series> = AXES
        .iter()
        .zip(pick)
        .map(|(&(axis, color), f)| Series::line(&format!("τ_{axis}"), color, column(records, f)))
        .collect();
    for (i, &(axis, color)) in AXES.iter().enumerate() {
        let bound = summary.a_priori.torque_max_Nm[i];
        let label = format!("±bound {axis} (a priori)");
        series.push(Series::level(Some(&label), color, bound, span));
        series.push(Series::level(None, color, -bound, span));
    }
    let mut limits = scenario.limits.torque_max_Nm.to_vec();
    limits.sort_by(f64::total_cmp);
    limits.dedup();
    for (k, &limit) in limits.iter().enumerate() {
        let label = (k == 0).then_some("±actuator limit");
        series.push(Series::level(label, C_LIMIT, limit, span));
        series.push(Series::level(None, C_LIMIT, -limit, span));
    }
    panel("torque.png", "Torque", "torque [N m]", series)
}

/// `|τ_i|` per axis against the paper's bound (Theorem 2, dashed) and the tight bound (solid
/// level, same colour): how much of each the run used.
fn bounds_panel(summary: &Summary, records: &[Record]) -> Panel {
    let span = time_span(records);
    let pick: [Field; 3] = [|r| r.torque_x_Nm, |r| r.torque_y_Nm, |r| r.torque_z_Nm];
    let mut series: Vec<Series> = Vec::new();
    for (i, (&(axis, color), f)) in AXES.iter().zip(pick).enumerate() {
        series.push(Series::line(
            &format!("|τ_{axis}|"),
            color,
            column(records, |r| f(r).abs()),
        ));
        let paper = summary.a_priori.torque_max_Nm[i];
        series.push(Series::level(
            Some(&format!("paper bound {axis}")),
            color,
            paper,
            &span,
        ));
        let tight = summary.a_priori.tight.torque_max_Nm[i];
        series.push(Series::line(
            &format!("tight bound {axis}"),
            color,
            vec![(span.start, tight), (span.end, tight)],
        ));
    }
    panel(
        BOUNDS_FILE,
        "Torque against the paper's and the tight bounds",
        "|torque| [N m]",
        series,
    )
}

/// Fig. 2c: norms of the saturated feedback and the filter states, with `√3 M_p` (each
/// component of `ubar_p` is below `M_p`).
fn filters_panel(scenario: &Scenario, records: &[Record], span: &Range<f64>) -> Panel {
    let series = vec![
        Series::line("|ubar_p|", C_X, column(records, |r| r.ubar_p_norm_m_s2)),
        Series::line("|u_f|", C_Y, column(records, |r| r.u_f_norm_m_s2)),
        Series::line("|u_s|", C_Z, column(records, |r| r.u_s_norm_m_s2)),
        Series::level(
            Some("√3 M_p"),
            C_LIMIT,
            3f64.sqrt() * scenario.gains.M_p,
            span,
        ),
    ];
    panel(
        "filters.png",
        "Saturated feedback and filter states",
        "norm [m/s²]",
        series,
    )
}

/// Fig. 2d: norms of the radial saturations `s_θ`, `s_ω` with their levels `M_θ`, `M_ω`.
fn saturations_panel(scenario: &Scenario, records: &[Record], span: &Range<f64>) -> Panel {
    let g = &scenario.gains;
    let series = vec![
        Series::line("|s_θ|", C_X, column(records, |r| r.s_theta_norm_Nm)),
        Series::line("|s_ω|", C_Y, column(records, |r| r.s_omega_norm_Nm)),
        Series::level(Some("M_θ"), C_X, g.M_theta, span),
        Series::level(Some("M_ω"), C_Y, g.M_omega, span),
    ];
    panel(
        "saturations.png",
        "Attitude saturation functions",
        "norm [N m]",
        series,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fly::files::test_support::{synthetic_records, synthetic_summary, temp_dir};

    #[test]
    fn writes_ten_non_empty_pngs() {
        let dir = temp_dir("plots");
        let files = write_plots(
            &dir,
            &Scenario::paper(),
            &synthetic_summary(),
            &synthetic_records(300),
        )
        .expect("plots");
        assert_eq!(files.len(), 10);
        assert_eq!(files[8], dir.join(OVERVIEW_FILE));
        assert_eq!(files[9], dir.join(BOUNDS_FILE));
        for f in &files {
            let bytes = std::fs::read(f).expect("read png");
            assert!(
                bytes.starts_with(b"\x89PNG"),
                "{} is not a PNG",
                f.display()
            );
            assert!(bytes.len() > 1000, "{} is nearly empty", f.display());
        }
        let _ = std::fs::remove_dir_all(dir);
    }

    #[test]
    fn empty_run_still_draws() {
        let dir = temp_dir("plots-empty");
        let files = write_plots(&dir, &Scenario::paper(), &synthetic_summary(), &[])
            .expect("plots of nothing");
        assert_eq!(files.len(), 10);
        let _ = std::fs::remove_dir_all(dir);
    }

    #[test]
    fn error_names_the_file() {
        let dir = temp_dir("plots-err").join("missing");
        let e = write_plots(
            &dir,
            &Scenario::paper(),
            &synthetic_summary(),
            &synthetic_records(10),
        )
        .expect_err("no such directory");
        assert!(format!("{e:#}").contains("position.png"), "{e:#}");
    }

    #[test]
    fn unwrap_removes_jumps_and_yaw_ends_near_reference() {
        let u = unwrap([3.0, -3.0, -2.9].into_iter());
        assert!((u[1] - (2.0 * PI - 3.0)).abs() < 1e-12, "{u:?}");
        let mut recs = synthetic_records(5);
        for r in &mut recs {
            r.yaw_ref_rad = 3.1;
            r.yaw_rad = -3.1;
        }
        let (yaw, reference) = yaw_series(&recs);
        let (y, d) = (yaw[4].1, reference[4].1);
        assert!(
            (y - d).abs() < PI && (y - (2.0 * PI - 3.1)).abs() < 1e-12,
            "{y} {d}"
        );
    }

    #[test]
    fn panel_files_are_distinct_and_eight() {
        let p = panels(
            &Scenario::paper(),
            &synthetic_summary(),
            &synthetic_records(3),
        );
        let mut files: Vec<_> = p.iter().map(|p| p.file).collect();
        files.sort_unstable();
        files.dedup();
        assert_eq!(files.len(), 8);
    }
}
