//! Files written by a run: the time series (CSV), the plots (PNG) and the summary (JSON).
//!
//! [`write_all`] writes everything into one directory; [`write_csv`], [`write_summary`] and
//! [`write_plots`] write the parts. Every error names the file that failed.

pub mod console;
pub mod csv;
pub mod plots;
pub mod summary;

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

use crate::fly::sim::{Record, Summary};
use crate::model::scenario::Scenario;

pub use self::csv::write_csv;
pub use self::plots::write_plots;
pub use self::summary::write_summary;

/// File name of the time series inside the output directory.
pub const CSV_FILE: &str = "timeseries.csv";
/// File name of the summary inside the output directory.
pub const SUMMARY_FILE: &str = "summary.json";

/// Writes `timeseries.csv`, `summary.json` and the PNG plots (see [`write_plots`]) into `dir`,
/// creating it (and its parents) if missing.
///
/// Returns the paths of the files written, CSV first, then the summary, then the plots.
///
/// Errors: the directory cannot be created, or a file cannot be written (the error names it).
pub fn write_all(
    dir: &Path,
    scenario: &Scenario,
    summary: &Summary,
    records: &[Record],
) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir)
        .with_context(|| format!("creating output directory {}", dir.display()))?;
    let csv_path = dir.join(CSV_FILE);
    write_csv(&csv_path, records)?;
    let summary_path = dir.join(SUMMARY_FILE);
    write_summary(&summary_path, summary)?;
    let mut written = vec![csv_path, summary_path];
    written.extend(write_plots(dir, scenario, summary, records)?);
    Ok(written)
}

/// Helpers shared by the tests of this module's files.
#[cfg(test)]
pub(crate) mod test_support {
    use std::path::PathBuf;

    use crate::fly::sim::{APriori, Final, Observed, PathLiftingReport, Record, Settling, Summary};

    /// A fresh, empty directory under the system temp dir, unique per test `name` and process.
    pub fn temp_dir(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("host-sim-output-{name}-{}", std::process::id()));
        // A leftover from an earlier run of the same process id would make the test lie.
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create temp dir");
        dir
    }

    /// A short synthetic run: decaying errors (reaching exactly zero at the end, to exercise
    /// the log-axis floor) and bounded commands.
    pub fn synthetic_records(n: usize) -> Vec<Record> {
        (0..n)
            .map(|k| {
                let t = k as f64 * 0.01;
                let decay = if k + 1 == n { 0.0 } else { (-3.0 * t).exp() };
                Record {
                    t_s: t,
                    x_m: t.cos() + decay,
                    y_m: t.sin(),
                    z_m: 4.5 + t.cos(),
                    x_ref_m: t.cos(),
                    y_ref_m: t.sin(),
                    z_ref_m: 4.5 + t.cos(),
                    yaw_rad: 3.0 * t.sin() + 0.5 * decay,
                    yaw_ref_rad: 3.0 * t.sin(),
                    position_error_m: decay,
                    mrp_error: 0.5 * decay,
                    thrust_N: 4.5 + decay,
                    torque_x_Nm: 0.2 * decay,
                    torque_y_Nm: -0.2 * decay,
                    torque_z_Nm: 0.1 * decay,
                    ubar_p_norm_m_s2: 3.0 * decay,
                    u_f_norm_m_s2: 1.0 - decay,
                    u_s_norm_m_s2: 2.0 * decay,
                    s_theta_norm_Nm: 0.2 * decay,
                    s_omega_norm_Nm: 0.04 * decay,
                    m_flips: u32::from(k > n / 2),
                    ..Record::default()
                }
            })
            .collect()
    }

    /// A summary consistent with [`synthetic_records`].
    pub fn synthetic_summary() -> Summary {
        Summary {
            precision: crate::model::scenario::Precision::F32,
            a_priori: APriori {
                thrust_min_N: 3.51,
                thrust_max_N: 6.19,
                torque_max_Nm: [0.29, 0.33, 0.48],
                angular_velocity_max_rad_s: 1.0,
                angular_acceleration_max_rad_s2: 2.0,
                feedback_torque_max_Nm: 0.25,
                feedback_torque_axes_Nm: None,
                feasible: true,
                conditions: vec![],
                tight: crate::bounds::certificate::TightReport {
                    torque_max_Nm: [0.2, 0.25, 0.3],
                    angular_velocity_max_rad_s: 0.8,
                    angular_acceleration_max_rad_s2: 1.0,
                    ratio_to_paper: crate::bounds::certificate::TightRatios {
                        torque: [0.2 / 0.29, 0.25 / 0.33, 0.3 / 0.48],
                        angular_velocity: 0.8,
                        angular_acceleration: 0.5,
                    },
                    relative_gap: 0.01,
                    feasible: true,
                    conditions: vec![],
                },
                no_dive_thrust_interval_N: None,
                integral: None,
            },
            observed: Observed {
                thrust_min_N: 4.5,
                thrust_max_N: 5.5,
                torque_abs_max_Nm: [0.2, 0.2, 0.1],
                angular_velocity_d_max_rad_s: 0.5,
                angular_acceleration_d_max_rad_s2: 0.5,
                samples_outside_a_priori_bounds: 0,
                samples_above_tight_bounds: 0,
                samples: 3,
                altitude_loss_m: 0.25,
            },
            final_: Final {
                time_s: 0.02,
                position_error_m: 0.0,
                mrp_error: 0.0,
                angular_velocity_error_rad_s: 0.0,
            },
            path_lifting: PathLiftingReport {
                q_hat_resets: 0,
                m_flips: 1,
            },
            settling: Settling {
                position_error_below_1mm_from_s: Some(0.02),
                mrp_error_below_1e_4_from_s: None,
            },
            mixer: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::test_support::*;
    use super::*;

    #[test]
    fn write_all_creates_the_directory_and_lists_every_file() {
        let dir = temp_dir("all").join("nested");
        let records = synthetic_records(200);
        let files =
            write_all(&dir, &Scenario::paper(), &synthetic_summary(), &records).expect("write_all");
        assert_eq!(files.len(), 2 + 10);
        assert_eq!(files[0], dir.join(CSV_FILE));
        assert_eq!(files[1], dir.join(SUMMARY_FILE));
        for f in &files {
            let len = std::fs::metadata(f).expect("file exists").len();
            assert!(len > 0, "{} is empty", f.display());
        }
        let _ = std::fs::remove_dir_all(dir.parent().expect("has parent"));
    }

    #[test]
    fn write_all_names_the_directory_it_cannot_create() {
        let base = temp_dir("all-err");
        let blocker = base.join("a-file");
        std::fs::write(&blocker, b"x").expect("write blocker");
        let dir = blocker.join("sub");
        let e = write_all(&dir, &Scenario::paper(), &synthetic_summary(), &[])
            .expect_err("a file is in the way");
        assert!(
            format!("{e:#}").contains(&dir.display().to_string()),
            "{e:#}"
        );
        let _ = std::fs::remove_dir_all(base);
    }
}
