//! Extremes of a flight, gathered from its per-tick records: what the end-to-end checks of the
//! paper scenario (SIL and PIL alike) compare with the certificate's a-priori bounds.

use controller_core::Bounds;

use super::record::SilRecord;

/// Extremes of the records of one run, fed one record at a time by [`FlightExtremes::observe`].
///
/// Times are after release \[s\]; thrust \[N\] and torques \[N m\] are the allocated `(T, τ)`
/// (body frame), counted only after release (`t > 0`), when the controller flies.
#[derive(Clone, Debug, PartialEq)]
pub struct FlightExtremes {
    /// Start of the window in which `max_error_late_m` is taken \[s\] after release.
    pub late_from_s: f64,
    /// Records seen.
    pub samples: u32,
    /// Largest tilt during the first 0.5 s after release \[rad\] (near π: it started inverted).
    pub max_tilt_early_rad: f64,
    /// Largest position error from `late_from_s` on \[m\].
    pub max_error_late_m: f64,
    /// Largest tilt from `late_from_s` on \[rad\] (the attitude has recovered when it stays
    /// within what the saturated position loop can ask for).
    pub max_tilt_late_rad: f64,
    /// Lowest height `z` after release \[m\] (z up): with the start height, the altitude lost.
    pub lowest_z_m: f64,
    /// Smallest and largest allocated thrust after release \[N\].
    pub thrust_range_n: (f64, f64),
    /// Largest allocated `|τ_i|` per body axis after release \[N m\].
    pub torque_max_nm: [f64; 3],
}

impl FlightExtremes {
    /// Nothing seen yet; the late window starts at `late_from_s` \[s\] after release.
    pub fn new(late_from_s: f64) -> Self {
        Self {
            late_from_s,
            samples: 0,
            max_tilt_early_rad: 0.0,
            max_error_late_m: 0.0,
            max_tilt_late_rad: 0.0,
            lowest_z_m: f64::INFINITY,
            thrust_range_n: (f64::INFINITY, 0.0),
            torque_max_nm: [0.0; 3],
        }
    }

    /// Takes one record into account.
    pub fn observe(&mut self, r: &SilRecord) {
        self.samples += 1;
        if r.t_s < 0.5 {
            self.max_tilt_early_rad = self.max_tilt_early_rad.max(r.tilt_rad);
        }
        if r.t_s > self.late_from_s {
            self.max_error_late_m = self.max_error_late_m.max(r.position_error_m);
            self.max_tilt_late_rad = self.max_tilt_late_rad.max(r.tilt_rad);
        }
        if r.t_s > 0.0 {
            self.lowest_z_m = self.lowest_z_m.min(r.z_m);
            let (low, high) = self.thrust_range_n;
            self.thrust_range_n = (low.min(r.thrust_N), high.max(r.thrust_N));
            for (m, t) in
                self.torque_max_nm
                    .iter_mut()
                    .zip([r.torque_x_Nm, r.torque_y_Nm, r.torque_z_Nm])
            {
                *m = m.max(t.abs());
            }
        }
    }

    /// Whether the allocated `(T, τ)` stayed inside the certificate's a-priori bounds:
    /// `T ∈ [T_min, T_max]` (Theorem 1, eq:LowerBoundT, eq:UpperBoundT) and `|τ_i|` at most the
    /// per-axis torque bound (Theorem 2). `false` too when no record came after release.
    pub fn inside(&self, bounds: &Bounds<f32>) -> bool {
        let (low, high) = self.thrust_range_n;
        let torque_max = [
            bounds.torque_max.x,
            bounds.torque_max.y,
            bounds.torque_max.z,
        ];
        low >= f64::from(bounds.thrust_min)
            && high <= f64::from(bounds.thrust_max)
            && self
                .torque_max_nm
                .iter()
                .zip(torque_max)
                .all(|(seen, bound)| *seen <= f64::from(bound))
    }
}
