//! Step-time statistics of the control task, from the DWT cycle counter: mean and maximum step
//! cycles per reporting window, the longest step on the board's clock (µs; on QEMU, where the
//! cycle counter reads 0, the only duration there is), and deadline overruns.
//!
//! The arithmetic is here (pure, host-tested); `main.rs` reads `DWT.CYCCNT` and the tick times.
//! `CYCCNT` is a free-running 32-bit counter at the core clock (168 MHz: it wraps every 25.6 s),
//! so a span is `end.wrapping_sub(start)`, valid for spans shorter than one wrap.
//!
//! A step *overruns* when it finishes after its deadline, the next tick: the lateness of its
//! start (how long after the scheduled tick the task ran) plus its own duration exceeds the
//! period. A step that is merely slow but still done before the next tick does not count.

/// Cycles between two `CYCCNT` readings, across one counter wrap.
pub const fn cycles_between(start: u32, end: u32) -> u32 {
    end.wrapping_sub(start)
}

/// Cycles → microseconds at `core_hz`.
pub fn cycles_to_us(cycles: u32, core_hz: u32) -> f32 {
    cycles as f32 * 1e6 / core_hz as f32
}

/// Whether a step that started `lateness_us` after its scheduled tick and ran `step_us` missed
/// the next tick, `period_us` after the scheduled one.
pub const fn is_overrun(lateness_us: u64, step_us: u64, period_us: u64) -> bool {
    lateness_us.saturating_add(step_us) > period_us
}

/// Accumulates step times over a reporting window (e.g. 1 s) and overruns since boot.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StepStats {
    steps: u32,
    sum_cycles: u64,
    max_cycles: u32,
    max_step_us: u64,
    window_overruns: u32,
    total_overruns: u32,
    total_steps: u64,
}

/// What one window of [`StepStats`] reports.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WindowReport {
    /// Steps in the window.
    pub steps: u32,
    /// Mean step \[cycles\] (0 if no step).
    pub mean_cycles: u32,
    /// Longest step \[cycles\].
    pub max_cycles: u32,
    /// Longest step on the board's clock \[µs\] (the duration the overrun rule uses).
    pub max_step_us: u64,
    /// Overruns in the window.
    pub overruns: u32,
    /// Overruns since boot.
    pub total_overruns: u32,
    /// Steps since boot.
    pub total_steps: u64,
}

impl StepStats {
    /// No step yet.
    pub const fn new() -> Self {
        Self {
            steps: 0,
            sum_cycles: 0,
            max_cycles: 0,
            max_step_us: 0,
            window_overruns: 0,
            total_overruns: 0,
            total_steps: 0,
        }
    }

    /// Records one step of `cycles` that took `step_us` \[µs\] on the board's clock; `overrun`
    /// from [`is_overrun`].
    pub fn record(&mut self, cycles: u32, step_us: u64, overrun: bool) {
        self.steps = self.steps.saturating_add(1);
        self.total_steps = self.total_steps.saturating_add(1);
        self.sum_cycles = self.sum_cycles.saturating_add(cycles as u64);
        self.max_cycles = self.max_cycles.max(cycles);
        self.max_step_us = self.max_step_us.max(step_us);
        if overrun {
            self.window_overruns = self.window_overruns.saturating_add(1);
            self.total_overruns = self.total_overruns.saturating_add(1);
        }
    }

    /// Records `ticks` control ticks that never ran (the task fell more than a period behind
    /// and skipped them): each is an overrun.
    pub fn record_missed(&mut self, ticks: u32) {
        self.window_overruns = self.window_overruns.saturating_add(ticks);
        self.total_overruns = self.total_overruns.saturating_add(ticks);
    }

    /// Steps in the current window.
    pub const fn window_steps(&self) -> u32 {
        self.steps
    }

    /// Overruns since boot.
    pub const fn total_overruns(&self) -> u32 {
        self.total_overruns
    }

    /// Reports the current window and starts a new one (the totals carry on).
    pub fn take_window(&mut self) -> WindowReport {
        let report = WindowReport {
            steps: self.steps,
            mean_cycles: if self.steps == 0 {
                0
            } else {
                (self.sum_cycles / self.steps as u64) as u32
            },
            max_cycles: self.max_cycles,
            max_step_us: self.max_step_us,
            overruns: self.window_overruns,
            total_overruns: self.total_overruns,
            total_steps: self.total_steps,
        };
        self.steps = 0;
        self.sum_cycles = 0;
        self.max_cycles = 0;
        self.max_step_us = 0;
        self.window_overruns = 0;
        report
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spans_across_the_wrap() {
        assert_eq!(cycles_between(100, 250), 150);
        assert_eq!(cycles_between(u32::MAX - 9, 20), 30);
        assert_eq!(cycles_between(7, 7), 0);
        assert!((cycles_to_us(168_000, 168_000_000) - 1000.0).abs() < 1e-3);
        assert!((cycles_to_us(84, 168_000_000) - 0.5).abs() < 1e-6);
    }

    #[test]
    fn overrun_rule() {
        // 10 ms period.
        assert!(!is_overrun(0, 9_999, 10_000));
        assert!(!is_overrun(0, 10_000, 10_000));
        assert!(is_overrun(0, 10_001, 10_000));
        assert!(is_overrun(6_000, 4_500, 10_000));
        assert!(!is_overrun(6_000, 4_000, 10_000));
        assert!(is_overrun(u64::MAX, 1, 10_000));
    }

    #[test]
    fn windows_mean_max_and_overruns() {
        let mut s = StepStats::new();
        assert_eq!(s.take_window(), WindowReport::default());
        for (c, us) in [(100, 7), (300, 2), (200, 5)] {
            s.record(c, us, false);
        }
        s.record(1000, 3, true);
        assert_eq!(s.window_steps(), 4);
        let w = s.take_window();
        assert_eq!(
            w,
            WindowReport {
                steps: 4,
                mean_cycles: 400,
                max_cycles: 1000,
                max_step_us: 7,
                overruns: 1,
                total_overruns: 1,
                total_steps: 4,
            }
        );
        s.record(50, 1, true);
        let w = s.take_window();
        assert_eq!((w.steps, w.mean_cycles, w.max_cycles), (1, 50, 50));
        assert_eq!(w.max_step_us, 1);
        assert_eq!((w.overruns, w.total_overruns, w.total_steps), (1, 2, 5));
        assert_eq!(s.total_overruns(), 2);
        // Skipped ticks are overruns, not steps.
        s.record_missed(3);
        assert_eq!(s.window_steps(), 0);
        let w = s.take_window();
        assert_eq!((w.steps, w.overruns, w.total_overruns), (0, 3, 5));
        assert_eq!(s.total_overruns(), 5);
        // A new window starts empty, the totals stay.
        let w = s.take_window();
        assert_eq!(
            (w.steps, w.max_cycles, w.max_step_us, w.overruns),
            (0, 0, 0, 0)
        );
        assert_eq!(w.total_overruns, 5);
    }
}
