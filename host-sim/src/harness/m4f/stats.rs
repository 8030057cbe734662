//! The figures of a bench run: instruction statistics, implied times and the budget check.

use std::path::Path;

use anyhow::{anyhow, ensure, Result};
use serde::Serialize;

use super::agreement::{Agreement, Floors};
use super::regions::{ArmRun, Kind};

/// The STM32F405's core clock \[Hz\] (the time implied by an instruction count assumes one
/// instruction per cycle: a lower bound).
pub const CORE_HZ: f64 = 168e6;
/// Min / median / max / mean of a set of instruction counts.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Stats {
    /// Number of steps.
    pub count: usize,
    /// Fewest instructions.
    pub min: u64,
    /// Median (lower median for an even count).
    pub median: u64,
    /// Most instructions.
    pub max: u64,
    /// Mean.
    pub mean: f64,
}

impl Stats {
    /// Statistics of `v`. Errors: `v` is empty.
    pub fn of(v: &[u64]) -> Result<Self> {
        ensure!(!v.is_empty(), "no steps");
        let mut s = v.to_vec();
        s.sort_unstable();
        Ok(Self {
            count: s.len(),
            min: s[0],
            median: s[(s.len() - 1) / 2],
            max: s[s.len() - 1],
            mean: s.iter().sum::<u64>() as f64 / s.len() as f64,
        })
    }
}

/// The figures of one step kind, with the implied times.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct StepFigures {
    /// Instruction counts (overhead removed).
    pub instructions: Stats,
    /// Implied time at [`CORE_HZ`], 1 instruction per cycle (a lower bound) \[µs\]:
    /// min, median, max.
    pub lower_bound_us: [f64; 3],
    /// Share of the CPU at 100 Hz, worst step (lower bound), in percent.
    pub cpu_percent_100hz: f64,
    /// Share of the CPU at 1 kHz, worst step (lower bound), in percent.
    pub cpu_percent_1khz: f64,
}

impl StepFigures {
    /// The figures of counts `v`.
    pub fn of(v: &[u64]) -> Result<Self> {
        let s = Stats::of(v)?;
        let us = |n: u64| n as f64 / CORE_HZ * 1e6;
        Ok(Self {
            instructions: s,
            lower_bound_us: [us(s.min), us(s.median), us(s.max)],
            cpu_percent_100hz: us(s.max) / 10_000.0 * 100.0,
            cpu_percent_1khz: us(s.max) / 1_000.0 * 100.0,
        })
    }
}

/// The budget check.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Budget {
    /// Most instructions allowed for a flight tick's full step.
    pub limit: u64,
    /// The largest full step measured.
    pub max_full_step: u64,
    /// `max_full_step ≤ limit`.
    pub within: bool,
}

/// Everything the bench reports (the `--json` file).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Figures {
    /// The ELF measured.
    pub elf: String,
    /// Core clock assumed for the implied times \[Hz\].
    pub core_hz: f64,
    /// Bracket overhead subtracted from every count \[instructions\].
    pub overhead_instructions: u64,
    /// One flight tick: 10 IMU samples, a pose frame, `control_tick`.
    pub full_step: StepFigures,
    /// `Controller::step` alone.
    pub controller_step: StepFigures,
    /// The arming tick (also decodes the arm and mission-start commands: two certificates).
    pub arm_tick_instructions: u64,
    /// Instructions executed by the whole bench program.
    pub total_instructions: u64,
    /// ARM vs host.
    pub agreement: Agreement,
    /// The floors used.
    pub floors: Floors,
    /// The budget check, when one was given.
    pub budget: Option<Budget>,
}

/// Builds the figures of a run and its comparison.
pub fn figures(
    elf: &Path,
    arm: &ArmRun,
    agreement: Agreement,
    floors: Floors,
    budget: Option<u64>,
) -> Result<Figures> {
    let full = StepFigures::of(&arm.instructions(Kind::Full))?;
    let controller = StepFigures::of(&arm.instructions(Kind::Controller))?;
    let arm_tick = arm
        .instructions(Kind::Arm)
        .first()
        .copied()
        .ok_or_else(|| anyhow!("no arming tick measured"))?;
    Ok(Figures {
        elf: elf.display().to_string(),
        core_hz: CORE_HZ,
        overhead_instructions: arm.overhead,
        full_step: full,
        controller_step: controller,
        arm_tick_instructions: arm_tick,
        total_instructions: arm.total_instructions,
        agreement,
        floors,
        budget: budget.map(|limit| Budget {
            limit,
            max_full_step: full.instructions.max,
            within: full.instructions.max <= limit,
        }),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stats_and_times() {
        let s = Stats::of(&[5, 1, 3, 4]).unwrap();
        assert_eq!((s.min, s.median, s.max), (1, 3, 5));
        let f = StepFigures::of(&[168_000]).unwrap();
        assert!((f.lower_bound_us[2] - 1000.0).abs() < 1e-9);
        assert!((f.cpu_percent_100hz - 10.0).abs() < 1e-9);
        assert!((f.cpu_percent_1khz - 100.0).abs() < 1e-9);
    }
}
