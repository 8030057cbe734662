//! The rate of the control law: 100 Hz (the paper's Section VI, `dt = 0.01 s`, the default),
//! 250, 500 or 1 000 Hz. Only these four: each is a whole number of microseconds and of the
//! 1 kHz IMU's samples per tick, so the lockstep and the flight board tick on exact periods,
//! and every one is measured (SIL, campaign, PIL; README "Law rate").
//!
//! What depends on the rate: the controller's filter propagation (exact for any sample period,
//! `controller_core::position::FilterPropagator`), the setpoint filter (exact,
//! (`firmware::flight_reference`) and the tick counts derived from times (the landed detector's
//! confirmation). What does not: the estimator and the Mahony filter (per IMU sample), the
//! telemetry (periods in µs) and the logs (per second of ticks).
//!
//! Shared with the build script (`build.rs` compiles this file), which reads the rate from the
//! flight file's `[design] control_rate_hz` or `FIRMWARE_CONTROL_RATE_HZ`.

/// One of the allowed control-law rates.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ControlRate {
    /// 100 Hz, period 10 ms: the paper's `dt = 0.01 s` (the default).
    #[default]
    Hz100,
    /// 250 Hz, period 4 ms.
    Hz250,
    /// 500 Hz, period 2 ms.
    Hz500,
    /// 1 000 Hz, period 1 ms (one IMU sample per tick at the 1 kHz IMU rate).
    Hz1000,
}

/// A requested rate that is not one of [`ControlRate::ALL`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UnsupportedRate {
    /// The rate asked for \[Hz\].
    pub hz: f64,
}

impl core::fmt::Display for UnsupportedRate {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(
            f,
            "control rate {} Hz is not supported: choose 100, 250, 500 or 1000 Hz",
            self.hz
        )
    }
}

impl ControlRate {
    /// Every allowed rate, slowest first.
    pub const ALL: [ControlRate; 4] = [Self::Hz100, Self::Hz250, Self::Hz500, Self::Hz1000];

    /// The rate for `hz` \[Hz\]. Errors: [`UnsupportedRate`] for anything but exactly 100, 250,
    /// 500 or 1000 (a non-finite or fractional value included).
    pub fn from_hz(hz: f64) -> Result<Self, UnsupportedRate> {
        Self::ALL
            .into_iter()
            .find(|r| f64::from(r.hz()) == hz)
            .ok_or(UnsupportedRate { hz })
    }

    /// The rate \[Hz\].
    pub const fn hz(self) -> u32 {
        match self {
            Self::Hz100 => 100,
            Self::Hz250 => 250,
            Self::Hz500 => 500,
            Self::Hz1000 => 1000,
        }
    }

    /// The period \[µs\] (exact: every rate divides 10⁶).
    pub const fn period_us(self) -> u64 {
        1_000_000 / self.hz() as u64
    }

    /// The period \[s\] as the law's `dt`: the `f32` nearest to `1/hz` (for 100 Hz exactly the
    /// literal `0.01`, the paper's `dt`).
    pub const fn period_s(self) -> f32 {
        match self {
            Self::Hz100 => 0.01,
            Self::Hz250 => 0.004,
            Self::Hz500 => 0.002,
            Self::Hz1000 => 0.001,
        }
    }

    /// Ticks in `span_us` \[µs\], rounded up and at least 1: a time-based setting (e.g. the
    /// landed detector's confirmation time) counted in ticks of this rate.
    pub const fn ticks_in(self, span_us: u64) -> u32 {
        let p = self.period_us();
        let n = span_us.div_ceil(p);
        if n == 0 {
            1
        } else if n > u32::MAX as u64 {
            u32::MAX
        } else {
            n as u32
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_four_rates_are_accepted() {
        for (hz, rate) in [
            (100.0, ControlRate::Hz100),
            (250.0, ControlRate::Hz250),
            (500.0, ControlRate::Hz500),
            (1000.0, ControlRate::Hz1000),
        ] {
            assert_eq!(ControlRate::from_hz(hz), Ok(rate));
        }
        for hz in [
            0.0,
            -100.0,
            99.0,
            100.5,
            200.0,
            2000.0,
            f64::NAN,
            f64::INFINITY,
        ] {
            let e = ControlRate::from_hz(hz).unwrap_err();
            assert!(e.hz.to_bits() == hz.to_bits());
        }
        let text = format!("{}", UnsupportedRate { hz: 300.0 });
        assert!(
            text.contains("300 Hz") && text.contains("100, 250, 500 or 1000"),
            "{text}"
        );
    }

    #[test]
    fn periods_agree_with_the_rate() {
        assert_eq!(ControlRate::default(), ControlRate::Hz100);
        // The paper's dt, bit for bit.
        assert_eq!(ControlRate::Hz100.period_s().to_bits(), 0.01f32.to_bits());
        for r in ControlRate::ALL {
            assert_eq!(r.period_us() * u64::from(r.hz()), 1_000_000);
            // The f32 period is the f32 nearest to 1/hz (computed independently in f64).
            let exact = 1.0 / f64::from(r.hz());
            assert_eq!(r.period_s(), exact as f32, "{r:?}");
        }
    }

    /// The law's filters (eq:FilterDynamics, exact propagation with `ubar_p` held) give the
    /// same state after 20 ms at every rate: `n` steps of `20 ms / n` equal one step of 20 ms
    /// (the exact solution's semigroup property; f64, the paper's gains), so a faster rate
    /// changes only how often `ubar_p` is sampled, not the filters' discretisation.
    #[test]
    fn the_filters_are_exact_at_every_rate() {
        use controller_core::position::FilterState;
        use nalgebra::Vector3;
        let gains = controller_core::Gains::<f64>::paper().position;
        let start = FilterState {
            u_f: Vector3::new(0.3, -1.2, 9.0),
            u_s: Vector3::new(-0.7, 0.4, 2.5),
        };
        let ubar = Vector3::new(1.1, -0.6, 0.2);
        let once = gains.propagate(&start, &ubar, 0.02);
        for rate in ControlRate::ALL {
            let n = rate.hz() / 50;
            let dt = 1.0 / f64::from(rate.hz());
            let p = gains.propagator(dt);
            let stepped = (0..n).fold(start, |f, _| p.apply(&f, &ubar));
            for (a, b) in [(stepped.u_f, once.u_f), (stepped.u_s, once.u_s)] {
                assert!(
                    (a - b).norm() < 1e-12 * (1.0 + b.norm()),
                    "{rate:?}: {a} vs {b}"
                );
            }
        }
    }

    #[test]
    fn time_spans_become_whole_ticks() {
        assert_eq!(ControlRate::Hz100.ticks_in(300_000), 30);
        assert_eq!(ControlRate::Hz1000.ticks_in(300_000), 300);
        assert_eq!(ControlRate::Hz250.ticks_in(300_000), 75);
        // Rounded up, never 0.
        assert_eq!(ControlRate::Hz100.ticks_in(10_001), 2);
        assert_eq!(ControlRate::Hz100.ticks_in(0), 1);
        assert_eq!(ControlRate::Hz1000.ticks_in(u64::MAX), u32::MAX);
    }
}
