//! Helpers every report shares: one Markdown table ([`markdown_table`]), one figure panel of
//! traces (`chart`), PNG files ([`png`]) and the text of an optional number ([`fmt_opt`]).
//! They depend on nothing else in host-sim, so every part can use them.

pub(crate) mod chart;
pub mod markdown_table;
pub mod png;

/// `x.xx` or `-` (an optional figure in a report: a settling time, a percentile).
pub fn fmt_opt(x: Option<f64>) -> String {
    x.map_or_else(|| "-".into(), |v| format!("{v:.2}"))
}
