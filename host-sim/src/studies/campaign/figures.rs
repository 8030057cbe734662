//! Non-time-series figures (histogram, x–y lines and scatter) for the campaign, ablation and
//! comparison reports. Time series use the shared panel of `output::chart`.
//!
//! Log axes are drawn as the base-10 logarithm of the data with the axis labelled `log10(…)`:
//! one coordinate type keeps this helper small.

use std::path::Path;

use anyhow::{Context, Result};
use plotters::element::DashedPathElement;
use plotters::prelude::*;

use crate::output::chart::FONT;
use crate::output::png::{ensure_font, write_png};

/// Size of every figure \[px\].
pub const SIZE: (u32, u32) = (900, 560);

/// Colours, in series order.
pub const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(90, 90, 90),
];

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    /// Solid line.
    Line,
    /// Dashed line (bounds, limits).
    Dashed,
    /// Dots.
    Points,
}

/// One series of an x–y figure.
#[derive(Clone, Debug)]
pub struct XySeries {
    /// Legend entry.
    pub label: String,
    /// Colour.
    pub color: RGBColor,
    /// Drawing style.
    pub style: Style,
    /// `(x, y)` points.
    pub points: Vec<(f64, f64)>,
}

/// Axis description: label and whether it is logarithmic.
#[derive(Clone, Debug)]
pub struct Axis {
    /// Label with unit.
    pub label: String,
    /// Base-10 log scale (non-positive values dropped).
    pub log: bool,
}

impl Axis {
    /// A linear axis.
    pub fn linear(label: &str) -> Self {
        Self {
            label: label.into(),
            log: false,
        }
    }
    /// A log axis.
    pub fn log(label: &str) -> Self {
        Self {
            label: format!("log10 {label}"),
            log: true,
        }
    }
    fn map(&self, v: f64) -> Option<f64> {
        let v = if self.log {
            (v > 0.0).then(|| v.log10())?
        } else {
            v
        };
        v.is_finite().then_some(v)
    }
}

/// The data range widened by 5 % below and `top` (a fraction of the span) above.
fn padded(lo: f64, hi: f64, top: f64) -> std::ops::Range<f64> {
    if !(lo.is_finite() && hi.is_finite()) {
        return 0.0..1.0;
    }
    let span = (hi - lo).abs().max(1e-9 * hi.abs().max(1.0));
    (lo - 0.05 * span)..(hi + top * span)
}

/// Draws an x–y figure to `path` (PNG).
///
/// Errors: the font or the PNG cannot be written (names the file).
pub fn xy_figure(path: &Path, title: &str, x: &Axis, y: &Axis, series: &[XySeries]) -> Result<()> {
    ensure_font()?;
    let mapped: Vec<Vec<(f64, f64)>> = series
        .iter()
        .map(|s| {
            s.points
                .iter()
                .filter_map(|&(a, b)| Some((x.map(a)?, y.map(b)?)))
                .collect()
        })
        .collect();
    let all = || mapped.iter().flatten();
    let xr = padded(
        all().map(|p| p.0).fold(f64::INFINITY, f64::min),
        all().map(|p| p.0).fold(f64::NEG_INFINITY, f64::max),
        0.05,
    );
    let yr = padded(
        all().map(|p| p.1).fold(f64::INFINITY, f64::min),
        all().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max),
        // Room above the data for the legend in the upper-right corner.
        0.05 + 0.07 * series.len() as f64,
    );
    write_png(path, SIZE, |root| {
        root.fill(&WHITE)?;
        let mut chart = ChartBuilder::on(root)
            .caption(title, (FONT, 22))
            .margin(14)
            .x_label_area_size(44)
            .y_label_area_size(76)
            .build_cartesian_2d(xr, yr)?;
        chart
            .configure_mesh()
            .x_desc(x.label.as_str())
            .y_desc(y.label.as_str())
            .label_style((FONT, 14))
            .axis_desc_style((FONT, 16))
            .light_line_style(WHITE.mix(0.0))
            .draw()?;
        for (s, pts) in series.iter().zip(&mapped) {
            let color = s.color;
            let style = ShapeStyle::from(&color).stroke_width(2);
            let anno = match s.style {
                Style::Line => chart.draw_series(LineSeries::new(pts.iter().copied(), style))?,
                Style::Dashed => {
                    chart.draw_series(DashedLineSeries::new(pts.iter().copied(), 8, 5, style))?
                }
                Style::Points => chart.draw_series(
                    pts.iter()
                        .map(|&p| Circle::new(p, 2, ShapeStyle::from(&color.mix(0.6)).filled())),
                )?,
            };
            if !s.label.is_empty() {
                let dashed = s.style == Style::Dashed;
                anno.label(s.label.as_str()).legend(
                    move |(lx, ly)| -> DynElement<'static, BitMapBackend<'_>, (i32, i32)> {
                        let sample = vec![(lx, ly), (lx + 24, ly)];
                        if dashed {
                            DashedPathElement::new(sample, 6, 4, style).into_dyn()
                        } else {
                            PathElement::new(sample, style).into_dyn()
                        }
                    },
                );
            }
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .label_font((FONT, 14))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.4))
            .draw()?;
        Ok(())
    })
    .with_context(|| format!("drawing {title}"))
}

/// Draws a histogram of `values` with `bins` equal bins over their range (or `range`).
///
/// Errors: as [`xy_figure`].
pub fn histogram(
    path: &Path,
    title: &str,
    x_label: &str,
    values: &[f64],
    bins: usize,
    range: Option<(f64, f64)>,
) -> Result<()> {
    ensure_font()?;
    let finite: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
    let (lo, hi) = range.unwrap_or_else(|| {
        let lo = finite.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = finite.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        if lo.is_finite() && hi > lo {
            (lo, hi)
        } else if lo.is_finite() {
            (lo - 0.5, lo + 0.5)
        } else {
            (0.0, 1.0)
        }
    });
    let bins = bins.max(1);
    let width = (hi - lo) / bins as f64;
    let mut counts = vec![0u64; bins];
    for v in &finite {
        let i = (((v - lo) / width).floor().max(0.0) as usize).min(bins - 1);
        counts[i] += 1;
    }
    let top = counts.iter().copied().max().unwrap_or(0).max(1) as f64 * 1.08;
    write_png(path, SIZE, |root| {
        root.fill(&WHITE)?;
        let mut chart = ChartBuilder::on(root)
            .caption(title, (FONT, 22))
            .margin(14)
            .x_label_area_size(44)
            .y_label_area_size(76)
            .build_cartesian_2d(lo..hi, 0.0..top)?;
        chart
            .configure_mesh()
            .x_desc(x_label)
            .y_desc("runs")
            .label_style((FONT, 14))
            .axis_desc_style((FONT, 16))
            .light_line_style(WHITE.mix(0.0))
            .draw()?;
        chart.draw_series(counts.iter().enumerate().map(|(i, &c)| {
            let x0 = lo + i as f64 * width;
            Rectangle::new(
                [(x0, 0.0), (x0 + width, c as f64)],
                ShapeStyle::from(&PALETTE[0].mix(0.75)).filled(),
            )
        }))?;
        Ok(())
    })
    .with_context(|| format!("drawing {title}"))
}

/// The empirical CDF of `values` as step points, scaled so that it reaches
/// `count(values) / total` (runs that never settle keep it below 1).
pub fn cdf_points(values: &[f64], total: usize, x_end: f64) -> Vec<(f64, f64)> {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    v.sort_by(f64::total_cmp);
    let n = total.max(1) as f64;
    let mut pts = vec![(0.0, 0.0)];
    for (i, x) in v.iter().enumerate() {
        pts.push((*x, i as f64 / n));
        pts.push((*x, (i + 1) as f64 / n));
    }
    pts.push((x_end, v.len() as f64 / n));
    pts
}

/// Draws one time-series panel (the shared `output::chart` panel) to `path`.
///
/// Errors: as [`xy_figure`].
pub fn time_series_png(path: &Path, panel: &crate::output::chart::Panel) -> Result<()> {
    ensure_font()?;
    write_png(path, SIZE, |root| crate::output::chart::draw(root, panel))
}
