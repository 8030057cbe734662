//! defmt's global logger for QEMU: each encoded byte goes out with the semihosting call
//! `SYS_WRITEC`, which QEMU sends to its semihosting console — a chardev of the runner's choice
//! (`-semihosting-config enable=on,target=native,chardev=ID`; host-sim uses a file,
//! `defmt.bin`). `defmt-semihosting` is not used because it writes through `SYS_WRITE` on
//! `:tt`, which QEMU 7.2 maps to its own stdout whatever the chardev.
//!
//! One trap per byte is slow on a real probe but cheap under QEMU, and this build logs little
//! (the boot banner, then 10 Hz summaries).

use core::sync::atomic::{AtomicBool, Ordering};

use cortex_m_semihosting::{nr, syscall};

#[defmt::global_logger]
struct Logger;

/// Set between `acquire` and `release`.
static TAKEN: AtomicBool = AtomicBool::new(false);
/// Interrupt state saved by `acquire`, restored by `release`.
static mut RESTORE: critical_section::RestoreState = critical_section::RestoreState::invalid();
/// The frame encoder; only touched inside the critical section.
static mut ENCODER: defmt::Encoder = defmt::Encoder::new();

fn write_bytes(bytes: &[u8]) {
    for b in bytes {
        // SAFETY: SYS_WRITEC reads one byte through the pointer, which is valid for the call.
        unsafe {
            syscall(nr::WRITEC, b);
        }
    }
}

// SAFETY: `acquire` enters a critical section (interrupts masked on this single core) and
// refuses re-entry, so `ENCODER` and `RESTORE` have one user at a time until `release`.
unsafe impl defmt::Logger for Logger {
    fn acquire() {
        // SAFETY: paired with the `release` in `Logger::release`.
        let restore = unsafe { critical_section::acquire() };
        if TAKEN.swap(true, Ordering::Relaxed) {
            panic!("defmt logger re-entered");
        }
        // SAFETY: inside the critical section, and the only user (see above).
        unsafe {
            RESTORE = restore;
            (*core::ptr::addr_of_mut!(ENCODER)).start_frame(write_bytes);
        }
    }

    unsafe fn flush() {}

    unsafe fn release() {
        // SAFETY: called after `acquire`, in its critical section.
        unsafe {
            (*core::ptr::addr_of_mut!(ENCODER)).end_frame(write_bytes);
            TAKEN.store(false, Ordering::Relaxed);
            critical_section::release(RESTORE);
        }
    }

    unsafe fn write(bytes: &[u8]) {
        // SAFETY: called between `acquire` and `release`.
        unsafe { (*core::ptr::addr_of_mut!(ENCODER)).write(bytes, write_bytes) }
    }
}
