//! Cortex-M4F instruction counts of the firmware's control step, and the agreement of its `f32`
//! outputs on ARM with the same computation on the host.
//!
//! The firmware's `step-bench` binary (`firmware/src/bin/step_bench`) runs the deterministic
//! sequence of [`firmware::step_inputs`] on QEMU's `mps2-an386` (Cortex-M4 with FPU) and
//! brackets every measured step with calls to `step_bench_begin` / `step_bench_end`. The TCG
//! plugin `firmware/qemu/insn_count.c`, given those functions' addresses (read here from the
//! ELF's symbol table), counts the guest instructions executed from the entry of the first to
//! the entry of the second. The first regions are empty: their count is the brackets' own
//! overhead, subtracted from every step. The binary prints each step's outputs as `f32` bit
//! patterns over semihosting; [`compare`] checks them against
//! [`firmware::step_inputs::run_sequence`] run natively.
//!
//! Instructions are not cycles: at 1 instruction per cycle, 168 MHz (the STM32F405's clock)
//! gives a **lower bound** on the time (flash wait states, FPU divide/square-root latencies,
//! load-use stalls and taken branches all add cycles on the real MCU).
//!
//! [`cross_check`] recounts the first regions independently from QEMU's own execution trace
//! (`-singlestep -d exec,nochain`: one translation block per instruction, one `Trace` line per
//! executed block).
//!
//! Files: [`elf`] (the markers' addresses from the symbol table), [`regions`] (what a measured
//! region is), [`run`] (the bench on QEMU through [`crate::harness::qemu`], the trace
//! recount), [`output`] (parsers of the bench's and the plugin's output), [`agreement`] (ARM vs
//! host), [`stats`] (the figures), [`render`](mod@render) (the table) and
//! [`profile`](mod@profile) (per function).

pub mod agreement;
pub mod elf;
pub mod output;
pub mod profile;
pub mod regions;
pub mod render;
pub mod run;
pub mod stats;

pub use agreement::{compare, host_records, Agreement, Floors, RELATIVE_TOLERANCE};
pub use elf::{elf32_functions, markers, Markers, BEGIN_SYMBOL, END_SYMBOL};
pub use output::{format_records, parse_bench_output, parse_plugin_output};
pub use profile::profile;
pub use regions::{ArmRun, Kind, Region};
pub use render::render;
pub use run::{cross_check, run_arm, BenchOptions};
pub use stats::{figures, Budget, Figures, Stats, StepFigures, CORE_HZ};
