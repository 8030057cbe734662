//! The rate study as Markdown tables (`rates.md`, the README's figures).

use crate::output::markdown_table::{Rule, Table};
use std::fmt::Write as _;

use super::RateStudy;

fn opt(x: Option<f64>, digits: usize) -> String {
    x.map_or_else(|| "-".to_string(), |v| format!("{v:.digits$}"))
}

fn axes(v: [f64; 3]) -> String {
    format!("{:.3} / {:.3} / {:.3}", v[0], v[1], v[2])
}

/// The SIL table (one row per scenario and rate), then the campaign's.
pub fn markdown(s: &RateStudy) -> String {
    let mut o = String::new();
    // Writing to a String cannot fail.
    let _ = writeln!(
        o,
        "SIL (firmware pipeline, build's vehicle, sensors over MAVLink, rotors with motor lag):\n"
    );
    let late = format!("max error after {} s (m)", super::sil_rows::LATE_FROM_S);
    let mut table = Table::new(
        &mut o,
        &[
            "scenario",
            "rate (Hz)",
            "RMS error, last 10 s (m)",
            &late,
            "peak abs(tau) x / y / z (N m)",
            "torque bound (N m)",
            "torque margin",
            "thrust range (N)",
            "thrust margin (N)",
            "mixer saturated",
            "end",
        ],
        Rule::Compact,
    );
    for r in &s.sil {
        table.row(&[
            r.scenario.to_string(),
            r.rate_hz.to_string(),
            format!("{:.4}", r.rms_error_last_10s_m),
            format!("{:.4}", r.max_error_late_m),
            axes(r.torque_peak_Nm),
            axes(r.torque_bound_Nm),
            format!("{:.1} %", 100.0 * r.torque_margin),
            format!("{:.2} to {:.2}", r.thrust_range_N[0], r.thrust_range_N[1]),
            format!("{:.2}", r.thrust_margin_N),
            format!("{:.1} %", 100.0 * r.mixer_saturated_fraction),
            r.final_state.to_string(),
        ]);
    }
    if s.campaign.is_empty() {
        return o;
    }
    let (vehicle, tau) = s.campaign_vehicle.clone().unwrap_or_default();
    let _ = writeln!(
        o,
        "\nCampaign ({} runs per rate, paper's law in f32, rotor plant of {vehicle}, motor time \
         constant {}):\n",
        s.campaign_runs,
        tau.map_or_else(|| "the vehicle's".to_string(), |t| format!("{t} s"))
    );
    let mut table = Table::new(
        &mut o,
        &[
            "rate (Hz)",
            "converged",
            "settling p50 / p99 (s)",
            "steady error p50 / max (m)",
            "peak abs(tau) x / y / z (N m)",
            "torque margin",
            "peak T / T_max (N)",
            "runs outside a-priori bounds",
            "mixer gave up",
            "failed",
        ],
        Rule::Compact,
    );
    for r in &s.campaign {
        table.row(&[
            r.rate_hz.to_string(),
            format!("{:.1} %", 100.0 * r.converged_fraction),
            format!("{} / {}", opt(r.settling_s[0], 2), opt(r.settling_s[1], 2)),
            format!(
                "{} / {}",
                opt(r.steady_error_m[0], 4),
                opt(r.steady_error_m[1], 4)
            ),
            axes(r.torque_peak_Nm),
            format!("{:.1} %", 100.0 * r.torque_margin),
            format!(
                "{:.2} / {:.2}",
                r.thrust_peak_and_bound_N[0], r.thrust_peak_and_bound_N[1]
            ),
            r.runs_outside_a_priori.to_string(),
            format!("{:.2} %", 100.0 * r.mixer_gave_up_fraction),
            r.failed_runs.to_string(),
        ]);
    }
    o
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::studies::rates::{CampaignRow, SilRow};

    /// One table line per row, in order; a missing percentile shows as `-`; no campaign table
    /// without campaign rows.
    #[test]
    fn one_line_per_row() {
        let sil = SilRow {
            scenario: "helix".into(),
            rate_hz: 250,
            ticks: 10,
            rms_error_last_10s_m: 0.0123,
            max_error_late_m: 0.5,
            torque_peak_Nm: [0.01, 0.02, 0.03],
            torque_bound_Nm: [0.1, 0.1, 0.1],
            torque_margin: 0.7,
            thrust_range_N: [20.0, 21.0],
            thrust_bound_N: [18.0, 24.0],
            thrust_margin_N: 2.0,
            mixer_saturated_fraction: 0.0,
            final_state: "armed".into(),
        };
        let mut study = RateStudy {
            sil: vec![
                sil.clone(),
                SilRow {
                    rate_hz: 1000,
                    ..sil
                },
            ],
            campaign: Vec::new(),
            campaign_vehicle: None,
            campaign_runs: 0,
        };
        let text = markdown(&study);
        let rows: Vec<_> = text.lines().filter(|l| l.starts_with("| helix")).collect();
        assert_eq!(rows.len(), 2);
        assert!(
            rows[0].starts_with("| helix | 250 | 0.0123 |"),
            "{}",
            rows[0]
        );
        assert!(rows[1].contains("| 70.0 % |"), "{}", rows[1]);
        assert!(!text.contains("Campaign"));
        study.campaign.push(CampaignRow {
            rate_hz: 500,
            runs: 4,
            converged_fraction: 0.5,
            settling_s: [Some(10.0), None],
            steady_error_m: [Some(0.001), Some(0.002)],
            torque_peak_Nm: [0.1; 3],
            torque_bound_Nm: [0.2; 3],
            torque_margin: 0.5,
            thrust_peak_and_bound_N: [5.0, 6.0],
            runs_outside_a_priori: 0,
            mixer_gave_up_fraction: 0.0,
            failed_runs: 0,
        });
        let text = markdown(&study);
        let row = text.lines().find(|l| l.starts_with("| 500 |")).unwrap();
        assert!(row.starts_with("| 500 | 50.0 % | 10.00 / - |"), "{row}");
    }
}
