//! Campaign statistics: the content of `campaign.json` (besides the configuration).

use serde::Serialize;

use super::metrics::RunMetrics;
use super::runner::RunResult;
use crate::model::rotor_plant::MixerCounts;

/// Order statistics of a sample (nearest-rank percentiles); all `None` when empty.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct Distribution {
    /// Number of values.
    pub count: usize,
    /// Smallest.
    pub min: Option<f64>,
    /// Median.
    pub p50: Option<f64>,
    /// 90th percentile.
    pub p90: Option<f64>,
    /// 99th percentile.
    pub p99: Option<f64>,
    /// Largest.
    pub max: Option<f64>,
    /// Mean.
    pub mean: Option<f64>,
}

impl Distribution {
    /// From values (non-finite values are dropped).
    pub fn of(values: impl IntoIterator<Item = f64>) -> Self {
        let mut v: Vec<f64> = values.into_iter().filter(|x| x.is_finite()).collect();
        v.sort_by(f64::total_cmp);
        let n = v.len();
        if n == 0 {
            return Self::default();
        }
        let rank = |p: f64| v[((p * n as f64).ceil() as usize).clamp(1, n) - 1];
        Self {
            count: n,
            min: Some(v[0]),
            p50: Some(rank(0.5)),
            p90: Some(rank(0.9)),
            p99: Some(rank(0.99)),
            max: Some(v[n - 1]),
            mean: Some(v.iter().sum::<f64>() / n as f64),
        }
    }
}

/// Bound checks, split by whether the theorems apply to the runs.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct BoundCounts {
    /// Runs counted.
    pub runs: u64,
    /// Samples checked.
    pub samples: u64,
    /// Samples outside the a-priori bounds (Theorems 1–2).
    pub samples_outside_a_priori: u64,
    /// Runs with at least one such sample.
    pub runs_outside_a_priori: u64,
    /// Samples above the tight bounds (torque, `|ω_d|`, `|ω̇_d|`).
    pub samples_above_tight: u64,
    /// Samples beyond the physical limits (before clipping).
    pub samples_beyond_limits: u64,
}

/// What the mixer gave up (rotor plant only), split like the bound counts.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct MixerSplit {
    /// Over the runs the theorems cover.
    pub nominal: MixerCounts,
    /// Over the runs with model errors, disturbances or motor lag.
    pub perturbed: MixerCounts,
}

/// Worst cases over the campaign against the bounds.
#[derive(Clone, Debug, Serialize, PartialEq)]
#[allow(non_snake_case)]
pub struct WorstCase {
    /// Smallest thrust command over all runs \[N\].
    pub thrust_min_N: f64,
    /// Largest thrust command \[N\].
    pub thrust_max_N: f64,
    /// Largest `|τ_i|` per axis [N m].
    pub torque_abs_max_Nm: [f64; 3],
    /// Largest `|ω_d|` [rad/s].
    pub omega_d_max_rad_s: f64,
    /// Largest `|ω̇_d|` [rad/s²].
    pub omega_d_dot_max_rad_s2: f64,
}

/// Switch / jump statistics.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct SwitchStats {
    /// Total attitude-error switches (paper: MRP flips) over all runs.
    pub switches_total: u64,
    /// Total memory resets (paper: `q̂` resets).
    pub resets_total: u64,
    /// Switches per run.
    pub switches_per_run: Distribution,
    /// Largest number of switches in any 1 s window, over all runs.
    pub max_switches_in_1s: u32,
    /// Largest number of jumps (switches + resets) in any 1 s window, over all runs.
    pub max_jumps_in_1s: u32,
}

/// The campaign's results.
#[derive(Clone, Debug, Serialize)]
#[allow(non_snake_case)]
pub struct CampaignStats {
    /// Runs attempted.
    pub runs: u64,
    /// Runs the controller refused a sample in (counted as not converged).
    pub failed_runs: u64,
    /// Runs converged (see the definition).
    pub converged: u64,
    /// `converged / runs`.
    pub fraction_converged: f64,
    /// The 180° starts: runs and converged.
    pub half_turn_runs: u64,
    /// Of which converged.
    pub half_turn_converged: u64,
    /// Settling times of the runs that settled \[s\].
    pub settling_time_s: Distribution,
    /// Time until the attitude error first drops below 90° \[s\].
    pub attitude_below_90deg_s: Distribution,
    /// Final position errors \[m\].
    pub final_position_error_m: Distribution,
    /// Final attitude errors \[deg\].
    pub final_attitude_error_deg: Distribution,
    /// Mean position error over the last 5 s of the converged runs \[m\].
    pub steady_position_error_m: Distribution,
    /// Worst cases.
    pub worst: WorstCase,
    /// Per-run largest thrust command \[N\].
    pub peak_thrust_N: Distribution,
    /// Per-run largest torque component `max_i |τ_i|` [N m].
    pub peak_torque_Nm: Distribution,
    /// Bound checks over the runs where the theorems apply.
    pub nominal: BoundCounts,
    /// Bound checks over the runs with model errors, disturbances or motor lag.
    pub perturbed: BoundCounts,
    /// Switches.
    pub switching: SwitchStats,
    /// Rotor plant only (absent with the ideal plant): samples where the firmware's mixer gave
    /// something up, and the most it gave up.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mixer: Option<MixerSplit>,
}

/// Summarises `results`; `nominal` says whether these runs are ones the theorems cover.
pub fn summarise(results: &[RunResult], nominal: bool) -> CampaignStats {
    let ok: Vec<&RunMetrics> = results.iter().filter_map(|r| r.metrics.as_ref()).collect();
    let converged = ok.iter().filter(|m| m.converged).count() as u64;
    let half: Vec<&RunResult> = results
        .iter()
        .filter(|r| r.start.starts_with("half_turn"))
        .collect();
    let mut counts = BoundCounts::default();
    for m in &ok {
        counts.runs += 1;
        counts.samples += m.samples;
        counts.samples_outside_a_priori += m.samples_outside_a_priori;
        counts.runs_outside_a_priori += u64::from(m.samples_outside_a_priori > 0);
        counts.samples_above_tight += m.samples_above_tight;
        counts.samples_beyond_limits += m.samples_beyond_limits;
    }
    let fold = |f: fn(&RunMetrics) -> f64, init: f64, pick: fn(f64, f64) -> f64| {
        ok.iter().map(|m| f(m)).fold(init, pick)
    };
    let worst = WorstCase {
        thrust_min_N: fold(|m| m.thrust_min_N, f64::INFINITY, f64::min),
        thrust_max_N: fold(|m| m.thrust_max_N, f64::NEG_INFINITY, f64::max),
        torque_abs_max_Nm: std::array::from_fn(|i| {
            ok.iter()
                .map(|m| m.torque_abs_max_Nm[i])
                .fold(0.0, f64::max)
        }),
        omega_d_max_rad_s: fold(|m| m.omega_d_max_rad_s, 0.0, f64::max),
        omega_d_dot_max_rad_s2: fold(|m| m.omega_d_dot_max_rad_s2, 0.0, f64::max),
    };
    let runs = results.len() as u64;
    let mixer = ok.iter().filter_map(|m| m.mixer).reduce(|mut a, b| {
        a.merge(&b);
        a
    });
    CampaignStats {
        runs,
        failed_runs: runs - ok.len() as u64,
        converged,
        fraction_converged: if runs > 0 {
            converged as f64 / runs as f64
        } else {
            0.0
        },
        half_turn_runs: half.len() as u64,
        half_turn_converged: half
            .iter()
            .filter(|r| r.metrics.as_ref().is_some_and(|m| m.converged))
            .count() as u64,
        settling_time_s: Distribution::of(ok.iter().filter_map(|m| m.settling_time_s)),
        attitude_below_90deg_s: Distribution::of(
            ok.iter().filter_map(|m| m.attitude_below_90deg_s),
        ),
        final_position_error_m: Distribution::of(ok.iter().map(|m| m.final_position_error_m)),
        final_attitude_error_deg: Distribution::of(ok.iter().map(|m| m.final_attitude_error_deg)),
        steady_position_error_m: Distribution::of(
            ok.iter()
                .filter(|m| m.converged)
                .map(|m| m.steady_position_error_m),
        ),
        worst,
        peak_thrust_N: Distribution::of(ok.iter().map(|m| m.thrust_max_N)),
        peak_torque_Nm: Distribution::of(
            ok.iter()
                .map(|m| m.torque_abs_max_Nm.iter().copied().fold(0.0, f64::max)),
        ),
        nominal: if nominal {
            counts.clone()
        } else {
            BoundCounts::default()
        },
        perturbed: if nominal {
            BoundCounts::default()
        } else {
            counts
        },
        switching: SwitchStats {
            switches_total: ok.iter().map(|m| u64::from(m.switches)).sum(),
            resets_total: ok.iter().map(|m| u64::from(m.resets)).sum(),
            switches_per_run: Distribution::of(ok.iter().map(|m| f64::from(m.switches))),
            max_switches_in_1s: ok.iter().map(|m| m.max_switches_per_1s).max().unwrap_or(0),
            max_jumps_in_1s: ok.iter().map(|m| m.max_jumps_per_1s).max().unwrap_or(0),
        },
        mixer: mixer.map(|counts| {
            if nominal {
                MixerSplit {
                    nominal: counts,
                    ..MixerSplit::default()
                }
            } else {
                MixerSplit {
                    perturbed: counts,
                    ..MixerSplit::default()
                }
            }
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_rank_percentiles() {
        let d = Distribution::of((1..=100).map(f64::from));
        assert_eq!(d.count, 100);
        assert_eq!(d.p50, Some(50.0));
        assert_eq!(d.p90, Some(90.0));
        assert_eq!(d.p99, Some(99.0));
        assert_eq!(d.max, Some(100.0));
        assert_eq!(d.mean, Some(50.5));
        assert_eq!(Distribution::of([f64::NAN]), Distribution::default());
    }
}
