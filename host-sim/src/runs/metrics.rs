//! Per-run metrics, accumulated sample by sample from [`crate::fly::closed_loop::LoopSample`]s.
//!
//! Definitions (also written into `campaign.json` by [`Convergence::describe`]):
//! - **settled from `t_s`**: the first sample time after which both the position error
//!   `|p − p_d|` and the attitude error `∠(R_dᵀR)` (true attitude against the controller's own
//!   desired attitude) stay below their thresholds until the end of the run; none if the last
//!   sample is above a threshold;
//! - **converged**: settled at or before `after_s` (so below both thresholds for every sample
//!   from `after_s` to the end);
//! - **outside the a-priori bounds**: a sample whose commanded thrust leaves `[T_min, T_max]` of
//!   Theorem 1 or whose `|τ_i|` exceeds Theorem 2's per-axis bound (relative slack 1e-5 for f32
//!   rounding, as in `summary.json`); commands are checked before any clipping;
//! - **beyond the physical limits**: a sample with `T < 0`, `T > T_max` or `|τ_i| > τ_max,i`
//!   (scenario `[limits]`), before clipping;
//! - **given up by the mixer** (rotor plant only): a sample whose command (after any clipping)
//!   the firmware's mixer could not realise on the rotors, with the thrust \[N\] and largest
//!   per-axis torque [N m] it gave up ([`crate::model::rotor_plant::MixReport`]);
//! - **switch rate**: the largest number of switches (or jumps) within any window of 1 s of
//!   samples (`round(1 s / dt)` consecutive sample intervals).

pub use crate::bounds::certificate::TightLimits;
use std::collections::VecDeque;

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::fly::closed_loop::LoopSample;
use crate::model::rotor_plant::MixerCounts;

/// The convergence thresholds.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Convergence {
    /// Position error threshold \[m\].
    pub position_m: f64,
    /// Attitude error threshold \[deg\].
    pub attitude_deg: f64,
    /// Converged means settled by this time \[s\].
    pub after_s: f64,
}

impl Default for Convergence {
    /// 5 cm and 2°, settled by 25 s (of the 30 s paper run).
    fn default() -> Self {
        Self {
            position_m: 0.05,
            attitude_deg: 2.0,
            after_s: 25.0,
        }
    }
}

impl Convergence {
    /// The default thresholds, settled by 5 s before the end of a run of `duration_s` \[s\]
    /// (the default's 25 s for the paper's 30 s; a run shorter than 5 s: from its start), so that
    /// a slower design flown for longer is judged on its own horizon with the same 5 s tail.
    pub fn for_duration(duration_s: f64) -> Self {
        Self {
            after_s: (duration_s - STEADY_WINDOW_S).max(0.0),
            ..Self::default()
        }
    }

    /// The definitions in words, with the numbers.
    pub fn describe(&self) -> String {
        format!(
            "converged: |p - p_d| < {} m and angle(R_d^T R) < {} deg for every sample from t = {} s \
             to the end of the run (R_d: the controller's own desired attitude; true state, not \
             the measurement). Settling time: the first sample time after which both errors stay \
             below these thresholds until the end.",
            self.position_m, self.attitude_deg, self.after_s
        )
    }
}

/// The bounds a run is checked against.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[allow(non_snake_case)]
pub struct BoundSet {
    /// Lower end of the certified thrust interval \[N\]: `T_min` of Theorem 1, or `T_floor`
    /// with the no-dive thrust ([`controller_core::ThrustMode::interval`]).
    pub thrust_min_N: f64,
    /// `T_max` of Theorem 1 \[N\] (upper end with either thrust mode).
    pub thrust_max_N: f64,
    /// Theorem 2's per-axis torque bound [N m].
    pub torque_max_Nm: [f64; 3],
    /// Physical `T_max` \[N\].
    pub limit_thrust_N: f64,
    /// Physical per-axis `τ_max` [N m].
    pub limit_torque_Nm: [f64; 3],
    /// The tight bounds ([`crate::bounds::tight`]); `None` where they are not computed (the
    /// design search, which certifies in closed form).
    pub tight: Option<TightLimits>,
}

/// Sliding count of events over the last `window` sample intervals: push the running total
/// at every sample; `max` is the most events within any `window` consecutive intervals.
#[derive(Clone, Debug)]
pub(crate) struct WindowMax {
    window: usize,
    totals: VecDeque<u32>,
    pub(crate) max: u32,
}

impl WindowMax {
    pub(crate) fn new(window: usize) -> Self {
        Self {
            window: window.max(1),
            totals: VecDeque::new(),
            max: 0,
        }
    }
    pub(crate) fn push(&mut self, total: u32) {
        self.totals.push_back(total);
        if self.totals.len() > self.window + 1 {
            self.totals.pop_front();
        }
        let first = self.totals.front().copied().unwrap_or(total);
        self.max = self.max.max(total - first);
    }
}

/// Everything measured along one run.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[allow(non_snake_case)]
pub struct RunMetrics {
    /// Samples taken.
    pub samples: u64,
    /// Settling time \[s\] (see the module docs); `None` if not settled at the end.
    pub settling_time_s: Option<f64>,
    /// Settled by `Convergence::after_s`.
    pub converged: bool,
    /// First time the attitude error is below 90° \[s\] (`None` if never): the time lost at a
    /// 180° start.
    pub attitude_below_90deg_s: Option<f64>,
    /// `|p − p_d|` at the last sample \[m\].
    pub final_position_error_m: f64,
    /// Attitude error at the last sample \[deg\].
    pub final_attitude_error_deg: f64,
    /// Mean `|p − p_d|` over the last 5 s \[m\] (steady-state error).
    pub steady_position_error_m: f64,
    /// Smallest thrust command \[N\].
    pub thrust_min_N: f64,
    /// Largest thrust command \[N\].
    pub thrust_max_N: f64,
    /// Largest `|τ_i|` per axis [N m].
    pub torque_abs_max_Nm: [f64; 3],
    /// Samples outside the a-priori bounds.
    pub samples_outside_a_priori: u64,
    /// Samples whose torque, `|ω_d|` or `|ω̇_d|` exceeded the tight bounds.
    pub samples_above_tight: u64,
    /// Samples beyond the physical limits.
    pub samples_beyond_limits: u64,
    /// Largest `|ω_d|` [rad/s].
    pub omega_d_max_rad_s: f64,
    /// Largest `|ω̇_d|` [rad/s²].
    pub omega_d_dot_max_rad_s2: f64,
    /// Attitude-error switches (MRP flips / sign changes) over the run.
    pub switches: u32,
    /// Memory resets over the run (paper's law only).
    pub resets: u32,
    /// Most switches within any 1 s.
    pub max_switches_per_1s: u32,
    /// Most jumps (switches + resets) within any 1 s.
    pub max_jumps_per_1s: u32,
    /// Rotor plant only: what the mixer gave up over the run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mixer: Option<MixerCounts>,
}

/// Accumulates [`RunMetrics`] from samples.
#[derive(Clone, Debug)]
pub struct MetricsAccumulator {
    convergence: Convergence,
    bounds: BoundSet,
    duration_s: f64,
    metrics: RunMetrics,
    settled_since: Option<f64>,
    switches_window: WindowMax,
    jumps_window: WindowMax,
    steady_sum: f64,
    steady_count: u64,
}

/// Steady-state window at the end of the run \[s\].
const STEADY_WINDOW_S: f64 = 5.0;
/// Rounding slack of the bound checks (f32 carries ~1e-7 relative error), as in `sim`.
const SLACK: f64 = 1e-5;

impl MetricsAccumulator {
    /// For a run of `duration_s` \[s\] sampled every `dt` \[s\].
    pub fn new(convergence: Convergence, bounds: BoundSet, duration_s: f64, dt: f64) -> Self {
        let window = (1.0 / dt).round() as usize;
        Self {
            convergence,
            bounds,
            duration_s,
            metrics: RunMetrics {
                samples: 0,
                settling_time_s: None,
                converged: false,
                attitude_below_90deg_s: None,
                final_position_error_m: f64::NAN,
                final_attitude_error_deg: f64::NAN,
                steady_position_error_m: f64::NAN,
                thrust_min_N: f64::INFINITY,
                thrust_max_N: f64::NEG_INFINITY,
                torque_abs_max_Nm: [0.0; 3],
                samples_outside_a_priori: 0,
                samples_above_tight: 0,
                samples_beyond_limits: 0,
                omega_d_max_rad_s: 0.0,
                omega_d_dot_max_rad_s2: 0.0,
                switches: 0,
                resets: 0,
                max_switches_per_1s: 0,
                max_jumps_per_1s: 0,
                mixer: None,
            },
            settled_since: None,
            switches_window: WindowMax::new(window),
            jumps_window: WindowMax::new(window),
            steady_sum: 0.0,
            steady_count: 0,
        }
    }

    /// Adds one sample.
    pub fn push(&mut self, s: &LoopSample<'_>) {
        let m = &mut self.metrics;
        let b = &self.bounds;
        let c = s.command;
        m.samples += 1;
        let thrust = c.thrust;
        let torque: Vector3<f64> = c.torque;
        m.thrust_min_N = m.thrust_min_N.min(thrust);
        m.thrust_max_N = m.thrust_max_N.max(thrust);
        for (peak, tau) in m.torque_abs_max_Nm.iter_mut().zip(torque.iter()) {
            *peak = peak.max(tau.abs());
        }
        let outside = thrust < b.thrust_min_N * (1.0 - SLACK)
            || thrust > b.thrust_max_N * (1.0 + SLACK)
            || (0..3).any(|i| torque[i].abs() > b.torque_max_Nm[i] * (1.0 + SLACK));
        m.samples_outside_a_priori += u64::from(outside);
        let (w_d, w_d_dot) = (
            c.desired_angular_velocity.norm(),
            c.desired_angular_acceleration.norm(),
        );
        if let Some(t) = &b.tight {
            m.samples_above_tight += u64::from(t.exceeded(&torque, w_d, w_d_dot, SLACK));
        }
        let beyond = !(0.0..=b.limit_thrust_N).contains(&thrust)
            || (0..3).any(|i| torque[i].abs() > b.limit_torque_Nm[i]);
        m.samples_beyond_limits += u64::from(beyond);
        m.omega_d_max_rad_s = m.omega_d_max_rad_s.max(w_d);
        m.omega_d_dot_max_rad_s2 = m.omega_d_dot_max_rad_s2.max(w_d_dot);
        m.switches = c.switches_total.switches;
        m.resets = c.switches_total.resets;
        self.switches_window.push(m.switches);
        self.jumps_window.push(m.switches + m.resets);
        m.max_switches_per_1s = self.switches_window.max;
        m.max_jumps_per_1s = self.jumps_window.max;

        if let Some(r) = &s.rotors {
            m.mixer
                .get_or_insert_with(MixerCounts::default)
                .push(&r.mix);
        }

        let attitude_deg = s.attitude_error_rad.to_degrees();
        if attitude_deg < 90.0 && m.attitude_below_90deg_s.is_none() {
            m.attitude_below_90deg_s = Some(s.t);
        }
        let below = s.position_error_m < self.convergence.position_m
            && attitude_deg < self.convergence.attitude_deg;
        if below {
            self.settled_since.get_or_insert(s.t);
        } else {
            self.settled_since = None;
        }
        if s.t >= self.duration_s - STEADY_WINDOW_S {
            self.steady_sum += s.position_error_m;
            self.steady_count += 1;
        }
        m.final_position_error_m = s.position_error_m;
        m.final_attitude_error_deg = attitude_deg;
    }

    /// The metrics of the run.
    pub fn finish(mut self) -> RunMetrics {
        let m = &mut self.metrics;
        m.settling_time_s = self.settled_since;
        m.converged = self
            .settled_since
            .is_some_and(|t| t <= self.convergence.after_s);
        if self.steady_count > 0 {
            m.steady_position_error_m = self.steady_sum / self.steady_count as f64;
        }
        self.metrics
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The default horizon is 5 s before the end: the fixed 25 s of the 30 s runs, bit for bit,
    /// and the same tail on a longer run; a run shorter than the tail is judged from its start.
    #[test]
    fn convergence_for_a_duration_keeps_a_five_second_tail() {
        assert_eq!(Convergence::for_duration(30.0), Convergence::default());
        let c = Convergence::for_duration(120.0);
        assert_eq!(
            (c.after_s, c.position_m, c.attitude_deg),
            (115.0, 0.05, 2.0)
        );
        assert_eq!(Convergence::for_duration(2.0).after_s, 0.0);
    }

    #[test]
    fn window_counts_events_in_any_second() {
        let mut w = WindowMax::new(100);
        // 3 events at samples 10..13, then 5 events spread over 150 samples.
        let mut total = 0;
        for k in 0..400u32 {
            if (10..13).contains(&k) || (k >= 200 && k % 30 == 0) {
                total += 1;
            }
            w.push(total);
        }
        // Samples 210, 240, 270, 300 fall inside one window of 100 intervals (4 events).
        assert_eq!(w.max, 4);
    }
}
