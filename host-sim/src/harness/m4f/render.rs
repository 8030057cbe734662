//! The human-readable table of a bench run.

use crate::output::markdown_table::{Rule, Table};
use std::fmt::Write as _;

use super::stats::Figures;

/// The human-readable table.
pub fn render(f: &Figures) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "Cortex-M4F (QEMU mps2-an386) instructions per step, bracket overhead ({} instructions) \
         removed; time at {:.0} MHz assuming 1 instruction/cycle is a LOWER BOUND (flash wait \
         states, FPU divide/sqrt latency and branches add cycles on the MCU)",
        f.overhead_instructions,
        f.core_hz / 1e6
    );
    let mut table = Table::new(
        &mut s,
        &[
            "step",
            "steps",
            "instructions min / median / max",
            "mean",
            "µs min / median / max (≥)",
            "CPU at 100 Hz (worst, ≥)",
            "CPU at 1 kHz (worst, ≥)",
        ],
        Rule::Spaced,
    );
    for (name, x) in [
        (
            "full step (10 IMU samples + pose frame + control_tick)",
            &f.full_step,
        ),
        ("controller step (Controller::step)", &f.controller_step),
    ] {
        let i = &x.instructions;
        table.row(&[
            name.to_string(),
            i.count.to_string(),
            format!("{} / {} / {}", i.min, i.median, i.max),
            format!("{:.0}", i.mean),
            format!(
                "{:.1} / {:.1} / {:.1}",
                x.lower_bound_us[0], x.lower_bound_us[1], x.lower_bound_us[2]
            ),
            format!("{:.2} %", x.cpu_percent_100hz),
            format!("{:.1} %", x.cpu_percent_1khz),
        ]);
    }
    let _ = writeln!(
        s,
        "arming tick (arm + mission start: two certificates): {} instructions ({:.1} µs ≥)",
        f.arm_tick_instructions,
        f.arm_tick_instructions as f64 / f.core_hz * 1e6
    );
    let a = &f.agreement;
    let _ = writeln!(
        s,
        "ARM vs host: {} values, {} bit-identical, largest relative difference {:.3e} ({}; \
         full steps {:.3e}, controller steps {:.3e}; {:.3e} leaving out the floored ones), \
         {} within their absolute floor only, {} outside tolerance (1e-5 relative)",
        a.compared,
        a.bit_identical,
        a.max_relative_difference,
        if a.worst.is_empty() { "-" } else { &a.worst },
        a.max_relative_difference_full,
        a.max_relative_difference_controller,
        a.max_relative_difference_within_tolerance,
        a.passed_by_floor,
        a.failures.len()
    );
    for c in &a.floor_cases {
        let _ = writeln!(s, "  within the floor only: {c}");
    }
    if let Some(b) = &f.budget {
        let _ = writeln!(
            s,
            "budget: largest full step {} instructions, limit {} ({})",
            b.max_full_step,
            b.limit,
            if b.within { "ok" } else { "EXCEEDED" }
        );
    }
    s
}
