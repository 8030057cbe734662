//! One generic time-series panel: what to draw ([`Panel`], [`Series`]) and how ([`draw`]).
//!
//! The eight plots of [`super::plots`] only describe their data; all drawing happens here, so
//! the individual PNGs and the overview grid look the same.

use std::ops::Range;

use anyhow::{Context, Result};
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;

/// Font family of every text; registered by [`super::plots`] before drawing.
pub const FONT: &str = "sans-serif";

/// Smallest value shown on a log axis: zeros and negatives are clamped to it, since a log axis
/// cannot place them.
pub const LOG_FLOOR: f64 = 1e-12;

/// `(t \[s\], y)` samples of one line, in time order.
pub type Points = Vec<(f64, f64)>;

/// Linear or base-10 logarithmic y axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scale {
    /// Linear.
    Linear,
    /// Base-10 logarithmic; values below [`LOG_FLOOR`] are clamped to it.
    Log,
}

/// One polyline of a panel.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend entry; `None` leaves it out of the legend (e.g. the mirrored `-bound` line).
    pub label: Option<String>,
    /// Line colour.
    pub color: RGBColor,
    /// Dashed (references and bounds) or solid (signals).
    pub dashed: bool,
    /// `(t \[s\], y)` points in time order.
    pub points: Points,
}

impl Series {
    /// A solid signal line.
    pub fn line(label: &str, color: RGBColor, points: Points) -> Self {
        Self {
            label: Some(label.to_owned()),
            color,
            dashed: false,
            points,
        }
    }

    /// A dashed line (a reference signal).
    pub fn dashed(label: &str, color: RGBColor, points: Points) -> Self {
        Self {
            dashed: true,
            ..Self::line(label, color, points)
        }
    }

    /// A dashed horizontal line at `y` over the time span `t`.
    pub fn level(label: Option<&str>, color: RGBColor, y: f64, t: &Range<f64>) -> Self {
        Self {
            label: label.map(str::to_owned),
            color,
            dashed: true,
            points: vec![(t.start, y), (t.end, y)],
        }
    }
}

/// Where the legend box goes.
pub type LegendAt = SeriesLabelPosition;

/// A whole panel: title, y axis and series.
#[derive(Clone, Debug)]
pub struct Panel {
    /// File name of the panel's own PNG.
    pub file: &'static str,
    /// Title above the plot.
    pub title: String,
    /// Y-axis label, with its unit.
    pub y_label: String,
    /// Y-axis scale.
    pub scale: Scale,
    /// The lines, drawn in order (later on top).
    pub series: Vec<Series>,
    /// Legend corner.
    pub legend_at: LegendAt,
}

/// Draws `panel` filling `area` (a whole PNG or one cell of a grid).
///
/// Errors: the backend failed to draw.
pub fn draw<DB>(area: &DrawingArea<DB, Shift>, panel: &Panel) -> Result<()>
where
    DB: DrawingBackend,
    DB::ErrorType: 'static,
{
    let series: Vec<Series> = panel
        .series
        .iter()
        .map(|s| Series {
            points: visible_points(&s.points, panel.scale),
            ..s.clone()
        })
        .collect();
    let x = time_range(&series);
    match panel.scale {
        // plotters' default labels suit a linear axis; on a log axis they print long decimals.
        Scale::Linear => draw_in(area, panel, &series, x, linear_range(&series), None),
        Scale::Log => draw_in(
            area,
            panel,
            &series,
            x,
            log_range(&series).log_scale(),
            Some(&|v: &f64| format!("{v:.0e}")),
        ),
    }
}

/// The drawing itself, generic over the y coordinate so linear and log share it.
fn draw_in<DB, Y>(
    area: &DrawingArea<DB, Shift>,
    panel: &Panel,
    series: &[Series],
    x: Range<f64>,
    y: Y,
    y_format: Option<&dyn Fn(&f64) -> String>,
) -> Result<()>
where
    DB: DrawingBackend,
    DB::ErrorType: 'static,
    Y: AsRangedCoord<Value = f64>,
    Y::CoordDescType: ValueFormatter<f64>,
{
    let ctx = || format!("drawing panel {:?}", panel.title);
    area.fill(&WHITE).with_context(ctx)?;
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, (FONT, 22))
        .margin(12)
        .x_label_area_size(42)
        .y_label_area_size(72)
        .build_cartesian_2d::<RangedCoordf64, Y>(x.into(), y)
        .with_context(ctx)?;
    let mut mesh = chart.configure_mesh();
    mesh.x_desc("time [s]")
        .y_desc(panel.y_label.as_str())
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 16))
        // Minor grid lines clutter the small overview cells; the major ones suffice.
        .light_line_style(WHITE.mix(0.0));
    if let Some(format) = y_format {
        mesh.y_label_formatter(format);
    }
    mesh.draw().with_context(ctx)?;

    for s in series {
        let style = ShapeStyle::from(&s.color).stroke_width(2);
        let annotation = if s.dashed {
            chart
                .draw_series(DashedLineSeries::new(s.points.iter().copied(), 8, 5, style))
                .with_context(ctx)?
        } else {
            chart
                .draw_series(LineSeries::new(s.points.iter().copied(), style))
                .with_context(ctx)?
        };
        if let Some(label) = &s.label {
            // The legend sample mirrors the line style, so references and bounds read as such.
            let dashed = s.dashed;
            annotation.label(label.as_str()).legend(
                move |(lx, ly)| -> DynElement<'static, DB, (i32, i32)> {
                    let sample = vec![(lx, ly), (lx + 24, ly)];
                    if dashed {
                        DashedPathElement::new(sample, 8, 5, style).into_dyn()
                    } else {
                        PathElement::new(sample, style).into_dyn()
                    }
                },
            );
        }
    }

    if series.iter().filter(|s| s.label.is_some()).count() > 1 {
        chart
            .configure_series_labels()
            .position(panel.legend_at.clone())
            .label_font((FONT, 14))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.4))
            .margin(8)
            .draw()
            .with_context(ctx)?;
    }
    Ok(())
}

/// Finite points only (a NaN would poison the axis range; the line joins across the dropped
/// points); on a log axis, values clamped to [`LOG_FLOOR`].
fn visible_points(points: &[(f64, f64)], scale: Scale) -> Points {
    points
        .iter()
        .filter(|(t, y)| t.is_finite() && y.is_finite())
        .map(|&(t, y)| match scale {
            Scale::Linear => (t, y),
            Scale::Log => (t, y.max(LOG_FLOOR)),
        })
        .collect()
}

/// Smallest and largest of `values`, or `None` when empty.
fn extent(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    values.fold(None, |acc, v| match acc {
        None => Some((v, v)),
        Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
    })
}

/// Time span of every point; a single instant is widened so the axis is not degenerate.
fn time_range(series: &[Series]) -> Range<f64> {
    let all = series.iter().flat_map(|s| s.points.iter().map(|p| p.0));
    match extent(all) {
        Some((lo, hi)) if hi > lo => lo..hi,
        Some((lo, _)) => lo..lo + 1.0,
        None => 0.0..1.0,
    }
}

/// Data span plus a 5 % margin, so lines at the extremes (bounds) stay visible.
fn linear_range(series: &[Series]) -> Range<f64> {
    let all = series.iter().flat_map(|s| s.points.iter().map(|p| p.1));
    let (lo, hi) = extent(all).unwrap_or((0.0, 1.0));
    let pad = if hi > lo {
        0.05 * (hi - lo)
    } else {
        0.5 * lo.abs().max(1.0)
    };
    lo - pad..hi + pad
}

/// Whole decades around the data, so the log axis starts and ends on a labelled tick.
fn log_range(series: &[Series]) -> Range<f64> {
    let all = series.iter().flat_map(|s| s.points.iter().map(|p| p.1));
    let (lo, hi) = extent(all).unwrap_or((LOG_FLOOR, 1.0));
    let lo = 10f64.powf(lo.max(LOG_FLOOR).log10().floor());
    let hi = 10f64.powf(hi.max(LOG_FLOOR).log10().ceil());
    if hi > lo {
        lo..hi
    } else {
        lo..lo * 10.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_points_are_clamped_and_non_finite_dropped() {
        let p = visible_points(&[(0.0, 0.0), (1.0, f64::NAN), (2.0, 1e-3)], Scale::Log);
        assert_eq!(p, vec![(0.0, LOG_FLOOR), (2.0, 1e-3)]);
    }

    #[test]
    fn log_range_snaps_to_decades() {
        let s = Series::line("a", BLACK, vec![(0.0, 3e-5), (1.0, 40.0)]);
        let r = log_range(&[s]);
        assert!(
            (r.start - 1e-5).abs() < 1e-18 && (r.end - 100.0).abs() < 1e-9,
            "{r:?}"
        );
    }

    #[test]
    fn degenerate_ranges_are_widened() {
        let s = Series::line("a", BLACK, vec![(2.0, 5.0)]);
        assert_eq!(time_range(std::slice::from_ref(&s)), 2.0..3.0);
        let r = linear_range(&[s]);
        assert!(r.start < 5.0 && r.end > 5.0);
    }
}
