//! Instruction counts and f32-on-ARM outputs of the control step, on QEMU's `mps2-an386`
//! (Cortex-M4F).
//!
//! Runs [`firmware::step_inputs`]'s sequence (calibration, upside-down arm, helix flight) through
//! the firmware's `FlightPipeline`, and the controller-core step alone along the same
//! trajectory. Every measured region is bracketed by calls to [`step_bench_begin`] and
//! [`step_bench_end`]; the TCG plugin `firmware/qemu/insn_count.c`, given the two functions'
//! addresses (read from this ELF's symbol table), counts the guest instructions executed from
//! the entry of `step_bench_begin` to the entry of `step_bench_end`. The first regions are
//! empty (`Z`): their count is the brackets' own overhead, which the host subtracts.
//!
//! Output over semihosting (stdout), one line per region, in bracket order, every float as its
//! IEEE-754 bit pattern (8 hex digits):
//!
//! - `Z <i>`: empty region `i`;
//! - `A <tick> <8 × hex>`: the arming tick's full step (throttles, achieved thrust and torque);
//! - `F <k> <8 × hex>`: flight tick `k`'s full step (same fields);
//! - `C <k> <4 × hex>`: controller step `k` (thrust \[N\], torque [N m]);
//! - `DONE regions=<n> off_path=<m>` last; then exit 0 through semihosting (exit 1 if some flight
//!   step left the flight path, or on a panic or fault).
//!
//! Build: `cargo fw-qemu --bin step-bench --features bench-fixtures` (the mps2-an386 release
//! build with the bench fixtures); run with `bash firmware/qemu/bench.sh`.
#![no_std]
#![no_main]

use core::panic::PanicInfo;

use cortex_m_rt::{entry, exception, ExceptionFrame};
use cortex_m_semihosting::{debug, hprintln};
use firmware::step_inputs::{self, Phase, StepSequence, ARM_TICK};
// defmt's global logger (the `-Tdefmt.x` link needs one if anything logs).
use defmt_semihosting as _;

/// Empty regions measured first (the brackets' overhead, expected constant).
const EMPTY_REGIONS: u32 = 3;

/// Region ids passed to the brackets (informative: the plugin identifies regions by order).
const ID_EMPTY: u32 = 0;
const ID_ARM: u32 = 1;
const ID_FULL: u32 = 2;
const ID_CONTROLLER: u32 = 3;

/// Start of a measured region. Never inlined, never mangled: the plugin counts from the
/// execution of its first instruction. The empty `asm!` (no `nomem`, no `pure`) is an opaque
/// side effect, so the compiler cannot move work across the call.
#[no_mangle]
#[inline(never)]
pub extern "C" fn step_bench_begin(id: u32) {
    // SAFETY: an empty instruction sequence that only names a register.
    unsafe { core::arch::asm!("/* begin {0} */", in(reg) id, options(nostack, preserves_flags)) }
}

/// End of a measured region: the plugin stops counting at its first instruction.
#[no_mangle]
#[inline(never)]
pub extern "C" fn step_bench_end(id: u32) {
    // SAFETY: as in `step_bench_begin`.
    unsafe { core::arch::asm!("/* end {0} */", in(reg) id, options(nostack, preserves_flags)) }
}

fn print_full(tag: char, n: u32, o: &step_inputs::FullOutputs) {
    let b = o.map(f32::to_bits);
    hprintln!(
        "{} {} {:08x} {:08x} {:08x} {:08x} {:08x} {:08x} {:08x} {:08x}",
        tag,
        n,
        b[0],
        b[1],
        b[2],
        b[3],
        b[4],
        b[5],
        b[6],
        b[7]
    );
}

#[entry]
fn main() -> ! {
    let mut regions = 0u32;
    for i in 0..EMPTY_REGIONS {
        step_bench_begin(ID_EMPTY);
        step_bench_end(ID_EMPTY);
        regions += 1;
        hprintln!("Z {}", i);
    }
    let mut pipeline = step_inputs::new_pipeline();
    let mut controller = step_inputs::new_controller();
    let mut off_path = 0u32;
    for inputs in StepSequence::new() {
        match inputs.phase {
            Phase::Setup => {
                let _ = step_inputs::full_step(&mut pipeline, &inputs);
            }
            Phase::Arm => {
                step_bench_begin(ID_ARM);
                let out = step_inputs::full_step(&mut pipeline, &inputs);
                step_bench_end(ID_ARM);
                regions += 1;
                print_full(
                    'A',
                    inputs.tick,
                    &step_inputs::full_outputs(&pipeline, &out),
                );
            }
            Phase::Flight => {
                let k = inputs.tick - ARM_TICK;
                step_bench_begin(ID_FULL);
                let out = step_inputs::full_step(&mut pipeline, &inputs);
                step_bench_end(ID_FULL);
                regions += 1;
                if !step_inputs::on_flight_path(&pipeline) {
                    off_path += 1;
                }
                print_full('F', k, &step_inputs::full_outputs(&pipeline, &out));

                let c = step_inputs::controller_inputs(k);
                step_bench_begin(ID_CONTROLLER);
                let r = step_inputs::controller_step(&mut controller, &c);
                step_bench_end(ID_CONTROLLER);
                regions += 1;
                let b = step_inputs::controller_outputs(&r).map(f32::to_bits);
                hprintln!(
                    "C {} {:08x} {:08x} {:08x} {:08x}",
                    k,
                    b[0],
                    b[1],
                    b[2],
                    b[3]
                );
            }
        }
    }
    hprintln!("DONE regions={} off_path={}", regions, off_path);
    debug::exit(if off_path == 0 {
        debug::EXIT_SUCCESS
    } else {
        debug::EXIT_FAILURE
    });
    loop {
        cortex_m::asm::nop();
    }
}

#[panic_handler]
fn panic(info: &PanicInfo) -> ! {
    hprintln!("PANIC {}", info);
    debug::exit(debug::EXIT_FAILURE);
    loop {
        cortex_m::asm::nop();
    }
}

#[exception]
unsafe fn HardFault(frame: &ExceptionFrame) -> ! {
    hprintln!("HARDFAULT pc={:#010x}", frame.pc());
    debug::exit(debug::EXIT_FAILURE);
    loop {
        cortex_m::asm::nop();
    }
}
