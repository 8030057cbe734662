//! The files a design writes: design.json, design.md, scenario.toml, firmware.toml and the
//! attitude plots.

use super::evaluate::Trial;
use super::flight::{ordered_toml, scenario_table, FlightSettings};
use super::options::Scored;
use super::reference::Reference;
use super::report::Report;
use super::vehicle::DesignVehicle;
use crate::output::chart::{LegendAt, Panel, Scale, Series};
use anyhow::{anyhow, Context as _, Result};
use plotters::style::RGBColor;
use std::path::{Path, PathBuf};

pub(crate) const COLORS: [RGBColor; 7] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
];

pub(crate) fn attitude_panel(file: &'static str, title: String, trials: &[Trial]) -> Panel {
    Panel {
        file,
        title,
        y_label: "attitude error [deg]".into(),
        scale: Scale::Linear,
        series: trials
            .iter()
            .zip(COLORS.iter().cycle())
            .map(|(t, c)| Series::line(&t.start, *c, t.attitude_trace.clone()))
            .collect(),
        legend_at: LegendAt::UpperRight,
    }
}

pub(crate) fn write_text(path: &Path, text: &str) -> Result<PathBuf> {
    std::fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))?;
    Ok(path.to_path_buf())
}

/// Writes `firmware.toml`: the vehicle file's tables, `[limits]`, `[gains]`, `[trajectory]` of
/// the scenario `table`, and `[design]`.
pub(crate) fn write_flight_file(
    dir: &Path,
    report: &Report,
    vehicle: &DesignVehicle,
    table: &toml::Table,
) -> Result<PathBuf> {
    let mut flight = toml::Table::new();
    for (k, v) in &vehicle.tables {
        flight.insert(k.clone(), v.clone());
    }
    for key in ["limits", "gains", "trajectory", "controller"] {
        if let Some(v) = table.get(key) {
            flight.insert(key.into(), v.clone());
        }
    }
    let mut design = toml::Table::new();
    design.insert("seed".into(), report.seed.to_string().into());
    design.insert(
        "objective".into(),
        report.objective.definition.clone().into(),
    );
    design.insert("margin".into(), report.rotor_fit.requested_margin.into());
    flight.insert("design".into(), toml::Value::Table(design));
    let text = ordered_toml(&flight)?;
    let header = format!(
        "# Flight file for the firmware build (FIRMWARE_FLIGHT_FILE), written by `host-sim design` for {}.\n\n",
        report.vehicle
    );
    write_text(&dir.join("firmware.toml"), &format!("{header}{text}"))
}

/// Writes every file of the design into `dir` (created if missing); returns their paths.
///
/// Errors: a file cannot be written (named).
pub fn write_outputs(
    dir: &Path,
    report: &Report,
    vehicle: &DesignVehicle,
    best: &Scored,
    reference: &Reference,
    controller_period_s: f64,
) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let mut files = Vec::new();
    let json = serde_json::to_string_pretty(report).map_err(|e| anyhow!("design.json: {e}"))?;
    files.push(write_text(&dir.join("design.json"), &json)?);

    let settings = FlightSettings {
        duration_s: report.duration_s,
        controller_period_s,
        controller: best.thrust.controller(),
    };
    let table = scenario_table(
        vehicle,
        &best.certified.limits,
        &best.mapped.gains,
        &reference.trajectory,
        &reference.initial,
        settings,
    )?;
    let header = format!(
        "# Certified design for {} by `host-sim design` (seed {}).\n# Runs as is: \
         host-sim --scenario scenario.toml\n\n",
        report.vehicle, report.seed
    );
    let text = ordered_toml(&table)?;
    files.push(write_text(
        &dir.join("scenario.toml"),
        &format!("{header}{text}"),
    )?);

    if report.certificate.paper_certified {
        files.push(write_flight_file(dir, report, vehicle, &table)?);
    }

    let e = &best.evaluation;
    let plots = [
        attitude_panel(
            "attitude_180.png",
            format!(
                "{}: 180 degree starts, motor time constant {} s",
                report.vehicle, vehicle.motor_time_constant_s
            ),
            &e.nominal,
        ),
        attitude_panel(
            "attitude_180_doubled_lag.png",
            format!(
                "{}: 180 degree starts, motor time constant doubled",
                report.vehicle
            ),
            &e.doubled_lag,
        ),
        attitude_panel(
            "attitude_upside_down.png",
            format!("{}: upside down at hover", report.vehicle),
            std::slice::from_ref(&e.upside_down),
        ),
    ];
    let mut drawn = Vec::new();
    for p in &plots {
        if p.series.is_empty() {
            continue;
        }
        let path = dir.join(p.file);
        crate::studies::campaign::figures::time_series_png(&path, p)?;
        drawn.push(p.file);
        files.push(path);
    }
    files.push(write_text(
        &dir.join("design.md"),
        &super::markdown::markdown(report, &drawn),
    )?);
    Ok(files)
}
