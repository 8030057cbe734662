//! Where the altitude goes when a run starts with the body z axis pointing down (upside down at
//! hover, most half turns): the *turn-over* (until the thrust direction is back above the
//! horizon, when the thrust starts to brake the fall) and the *braking* after it.
//!
//! An engineer reading "89 m lost upside down" needs to know which lever to pull: a slow
//! turn-over is the attitude feedback's torque near the half turn (the radial MRP term, whose
//! level yaw caps: docs/tilt-priority.md); a long braking is the position loop's level
//! (`M_p`, or the vertical channel's `M_up`: docs/vertical-channel.md) and the thrust interval.

use serde::Serialize;

/// The state of a run when the body z axis first comes back above the horizon (inertial
/// frame, z up). Source: this project's design report (docs/design.md, "Objective and
/// constraints"); not from the paper.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct TurnOver {
    /// Time from the start \[s\].
    pub time_s: f64,
    /// `z(0) − z` at that time \[m\] (inertial z up).
    pub altitude_loss_m: f64,
    /// `−v_z` at that time [m/s]: how fast the vehicle is sinking when braking can start.
    pub sink_rate_m_s: f64,
}

impl TurnOver {
    /// The mean braking deceleration [m/s²] that stops the sink rate over the altitude lost
    /// after the turn-over: `v² / (2 (loss − loss at turn-over))`, for a run whose whole loss
    /// is `total_loss_m` \[m\]. `None` when the vehicle was not sinking at the turn-over or lost
    /// nothing after it.
    pub fn mean_braking_m_s2(&self, total_loss_m: f64) -> Option<f64> {
        let after = total_loss_m - self.altitude_loss_m;
        (self.sink_rate_m_s > 0.0 && after > 0.0)
            .then(|| self.sink_rate_m_s * self.sink_rate_m_s / (2.0 * after))
    }
}

/// Watches a run sample by sample and records its [`TurnOver`]: the first sample whose body z
/// axis (inertial frame) has a positive vertical component, when the run started with it at or
/// below the horizon. Runs that start upright never record one. No errors: every input is a
/// sample of a simulated run. Source: as [`TurnOver`].
#[derive(Clone, Copy, Debug)]
pub struct TurnOverWatch {
    z0: f64,
    started_down: Option<bool>,
    found: Option<TurnOver>,
}

impl TurnOverWatch {
    /// A watch for a run starting at altitude `z0_m` \[m\].
    pub fn new(z0_m: f64) -> Self {
        Self {
            z0: z0_m,
            started_down: None,
            found: None,
        }
    }

    /// One sample: time `t_s` \[s\], the vertical component of the body z axis in the inertial
    /// frame `body_z_up` (`e₃ᵀ R e₃`, in `[−1, 1]`), altitude `z_m` \[m\], vertical velocity
    /// `v_z_m_s` [m/s] (inertial, up).
    pub fn push(&mut self, t_s: f64, body_z_up: f64, z_m: f64, v_z_m_s: f64) {
        let down = *self.started_down.get_or_insert(body_z_up <= 0.0);
        if down && self.found.is_none() && body_z_up > 0.0 {
            self.found = Some(TurnOver {
                time_s: t_s,
                altitude_loss_m: self.z0 - z_m,
                sink_rate_m_s: -v_z_m_s,
            });
        }
    }

    /// The turn-over, if the run started with the body z axis down and turned it up.
    pub fn finish(self) -> Option<TurnOver> {
        self.found
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Given a run that starts upside down and rolls upright at a constant rate while falling
    /// freely, when watched, then the turn-over is where the body z axis crosses the horizon
    /// (a quarter of the roll's period after the start, to one sample) with the free fall's
    /// loss and speed there.
    #[test]
    fn a_free_fall_rolling_upright_turns_over_after_half_its_half_turn() {
        let (g, rate, dt) = (9.81, 2.0, 1e-3);
        let mut w = TurnOverWatch::new(5.0);
        for k in 0..2000 {
            let t = k as f64 * dt;
            let angle = std::f64::consts::PI - rate * t; // from the half turn towards upright
            w.push(t, angle.cos(), 5.0 - 0.5 * g * t * t, -g * t);
        }
        let o = w.finish().expect("turned over");
        let t_cross = std::f64::consts::FRAC_PI_2 / rate;
        assert!((o.time_s - t_cross).abs() <= dt, "{o:?} vs {t_cross}");
        assert!((o.altitude_loss_m - 0.5 * g * o.time_s * o.time_s).abs() < 1e-12);
        assert!((o.sink_rate_m_s - g * o.time_s).abs() < 1e-12);
        // Stopping from v over d more metres takes v²/(2d).
        let total = o.altitude_loss_m + 3.0;
        let braking = o.mean_braking_m_s2(total).expect("sinking");
        assert!((braking - o.sink_rate_m_s.powi(2) / 6.0).abs() < 1e-12);
    }

    /// Given a run that starts upright (even if it tilts past the horizon later), then it
    /// records no turn-over; and one that never comes back up records none either.
    #[test]
    fn upright_starts_and_runs_that_stay_down_record_nothing() {
        let mut upright = TurnOverWatch::new(0.0);
        for (k, up) in [1.0, 0.2, -0.3, 0.5].into_iter().enumerate() {
            upright.push(k as f64, up, 0.0, 0.0);
        }
        assert_eq!(upright.finish(), None);
        let mut down = TurnOverWatch::new(0.0);
        for k in 0..10 {
            down.push(k as f64, -1.0, -(k as f64), -1.0);
        }
        assert_eq!(down.finish(), None);
        let rising = TurnOver {
            time_s: 1.0,
            altitude_loss_m: 2.0,
            sink_rate_m_s: -1.0,
        };
        assert_eq!(rising.mean_braking_m_s2(5.0), None);
    }
}
