//! The software-in-the-loop half of the rate study: one SIL scenario (the firmware's pipeline,
//! its sensors over MAVLink, rotors with motor lag) flown at one law rate, reduced to a row.

use anyhow::Result;
use serde::Serialize;

use crate::harness::sil::{self, scenarios, FlightExtremes};

/// From this time after release \[s\] the flight counts as tracking (the late window of
/// [`FlightExtremes`]): the paper scenario's flip and fall are over by then.
pub const LATE_FROM_S: f64 = 10.0;

/// One SIL scenario at one rate.
#[derive(Clone, Debug, Serialize, PartialEq)]
#[allow(non_snake_case)]
pub struct SilRow {
    /// SIL scenario name.
    pub scenario: String,
    /// The law's rate \[Hz\].
    pub rate_hz: u32,
    /// Control ticks recorded.
    pub ticks: u32,
    /// RMS position error over the last 10 s of flight \[m\] (SIL's summary).
    pub rms_error_last_10s_m: f64,
    /// Largest position error from [`LATE_FROM_S`] on \[m\].
    pub max_error_late_m: f64,
    /// Largest allocated `|τ_i|` after release, per body axis \[N m\].
    pub torque_peak_Nm: [f64; 3],
    /// The certificate's per-axis torque bound (Theorem 2) \[N m\].
    pub torque_bound_Nm: [f64; 3],
    /// Smallest `1 − peak_i / bound_i` over the axes \[dimensionless\]: the torque bound's
    /// margin left unused (negative: a bound was exceeded).
    pub torque_margin: f64,
    /// Allocated thrust range after release \[N\].
    pub thrust_range_N: [f64; 2],
    /// The certificate's thrust interval `[T_min, T_max]` (Theorem 1) \[N\].
    pub thrust_bound_N: [f64; 2],
    /// Smallest distance of the thrust to either end of its interval \[N\] (negative: outside).
    pub thrust_margin_N: f64,
    /// Fraction of the ticks in which the mixer gave something up \[dimensionless\].
    pub mixer_saturated_fraction: f64,
    /// Flight state at the end (`armed` when it flew the whole mission).
    pub final_state: String,
}

/// Flies SIL scenario `name` with `seed` at `rate_hz` \[Hz\] and reduces it to a row.
///
/// Errors: unknown scenario or unsupported rate; the firmware refuses the set-up.
pub fn fly(name: &str, seed: u64, rate_hz: f64) -> Result<SilRow> {
    let mut setup = scenarios::load(name, seed)?;
    setup.set_control_rate_hz(rate_hz)?;
    let bounds = setup.a_priori_bounds()?;
    let mut seen = FlightExtremes::new(LATE_FROM_S);
    let summary = sil::run(&setup, |r| seen.observe(r))?;
    let torque_bound = [
        f64::from(bounds.torque_max.x),
        f64::from(bounds.torque_max.y),
        f64::from(bounds.torque_max.z),
    ];
    let torque_margin = seen
        .torque_max_nm
        .iter()
        .zip(torque_bound)
        .map(|(peak, bound)| 1.0 - peak / bound)
        .fold(f64::INFINITY, f64::min);
    let (low, high) = seen.thrust_range_n;
    let thrust_bound = [f64::from(bounds.thrust_min), f64::from(bounds.thrust_max)];
    Ok(SilRow {
        scenario: setup.name.clone(),
        rate_hz: setup.flight.control_rate.hz(),
        ticks: seen.samples,
        rms_error_last_10s_m: summary.rms_position_error_last_10s_m,
        max_error_late_m: seen.max_error_late_m,
        torque_peak_Nm: seen.torque_max_nm,
        torque_bound_Nm: torque_bound,
        torque_margin,
        thrust_range_N: [low, high],
        thrust_bound_N: thrust_bound,
        thrust_margin_N: (low - thrust_bound[0]).min(thrust_bound[1] - high),
        mixer_saturated_fraction: f64::from(summary.mixer_saturated_ticks)
            / f64::from(seen.samples.max(1)),
        final_state: summary.final_state,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The law at 1 kHz ticks ten times as often as at 100 Hz over the same hold and flight
    /// (one tick per period, both ends included), flies the whole mission and stays inside the
    /// certificate's bounds; a rate outside the four is refused by name.
    #[test]
    fn the_helix_at_100_hz_and_1_khz() {
        let setup = scenarios::by_name("helix", 1).unwrap();
        let ticks = |hz: f64| ((setup.hold_s + setup.duration_s) * hz).round() as u32 + 1;
        let slow = fly("helix", 1, 100.0).unwrap();
        let fast = fly("helix", 1, 1000.0).unwrap();
        assert_eq!((slow.ticks, fast.ticks), (ticks(100.0), ticks(1000.0)));
        for r in [&slow, &fast] {
            assert_eq!(r.final_state, "armed", "{r:?}");
            assert!(r.torque_margin > 0.0 && r.thrust_margin_N > 0.0, "{r:?}");
            // Converged on the helix: centimetres, as the 100 Hz SIL tests ask.
            assert!(r.rms_error_last_10s_m < 0.05, "{r:?}");
        }
        let e = format!("{:#}", fly("helix", 1, 400.0).unwrap_err());
        assert!(
            e.contains("400 Hz") && e.contains("100, 250, 500 or 1000"),
            "{e}"
        );
    }
}
