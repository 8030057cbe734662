//! The MAVLink link on the CMSDK APB UART0 of `mps2-an386` (ARM DDI 0479C, "APB UART"), which
//! QEMU connects to its first serial port (`-serial stdio`: the simulator's pipe).
//!
//! Receive: the RX interrupt masks its NVIC line and wakes [`rx_task`], which moves every
//! waiting byte into [`LINK_RX`] — waiting for room rather than dropping, and leaving the byte
//! in the UART meanwhile, so QEMU holds back the rest (flow control, which the lockstep
//! simulation relies on) — then unmasks the line. The UART's own RX interrupt enable stays on:
//! QEMU only flags a byte that arrives while it is on, so turning it off would lose the wake-up
//! of a byte that lands between the last read and the re-enable. Transmit: [`tx_task`] writes the telemetry bytes, yielding while the
//! transmitter is full. No DMA: QEMU's UART takes one byte at a time anyway.

use core::ptr::{read_volatile, write_volatile};

use cortex_m::interrupt::InterruptNumber;
use cortex_m::peripheral::NVIC;
use embassy_futures::yield_now;
use embassy_sync::blocking_mutex::raw::CriticalSectionRawMutex;
use embassy_sync::signal::Signal;
use firmware::app::queues::{count, IO, LINK_RX, LINK_TX};

use crate::time_driver::CORE_HZ;

/// UART0 base address (AN386 memory map).
const BASE: usize = 0x4000_4000;
/// Data register: read the received byte, write a byte to send.
const DATA: usize = 0x00;
/// State: bit 0 transmitter full, bit 1 receiver full, bits 2/3 TX/RX overrun (write 1 clears).
const STATE: usize = 0x04;
/// Control: bit 0 TX enable, bit 1 RX enable, bit 3 RX interrupt enable, bit 5 RX overrun
/// interrupt enable.
const CTRL: usize = 0x08;
/// Interrupt status (read) / clear (write 1): bit 1 RX, bit 3 RX overrun.
const INTCLEAR: usize = 0x0C;
/// Baud divider (≥ 16).
const BAUDDIV: usize = 0x10;

const STATE_TX_FULL: u32 = 1 << 0;
const STATE_RX_FULL: u32 = 1 << 1;
const STATE_RX_OVERRUN: u32 = 1 << 3;
const CTRL_TX_EN: u32 = 1 << 0;
const CTRL_RX_EN: u32 = 1 << 1;
const CTRL_RX_INT: u32 = 1 << 3;
const INT_RX: u32 = 1 << 1;
const INT_RX_OVERRUN: u32 = 1 << 3;

/// UART0 receive interrupt number (QEMU `hw/arm/mps2.c`: UART *n* RX is IRQ 2*n*, TX 2*n*+1).
pub const RX_IRQ: u16 = 0;

/// The UART0 receive interrupt line.
#[derive(Clone, Copy)]
pub struct RxIrq;

// SAFETY: IRQ 0 is a valid external interrupt of the AN386 NVIC.
unsafe impl InterruptNumber for RxIrq {
    fn number(self) -> u16 {
        RX_IRQ
    }
}

/// Link baud rate \[bit/s\] (QEMU does not pace the bytes by it; a real MPS2 would).
const BAUD: u32 = 921_600;

/// Empty polls of the receiver before the task goes back to sleep. QEMU hands over one byte per
/// turn of its I/O loop, so sleeping after each byte pays an interrupt and two wake-ups per
/// byte; polling a little longer catches the next one. Measured with 2 s of 1 kHz
/// `HIL_SENSOR` in one burst: 9.3 s of wall time with 2000 polls, 13–15 s with 1 or 200.
const RX_SPIN: u32 = 2_000;

static RX_READY: Signal<CriticalSectionRawMutex, ()> = Signal::new();

fn read(offset: usize) -> u32 {
    // SAFETY: a documented UART0 register, word-aligned; reads have no side effect except
    // DATA, whose side effect (taking the byte) is the intent.
    unsafe { read_volatile((BASE + offset) as *const u32) }
}

fn write(offset: usize, value: u32) {
    // SAFETY: a documented UART0 register, word-aligned.
    unsafe { write_volatile((BASE + offset) as *mut u32, value) }
}

/// Enables the transmitter, the receiver and its interrupt. Call before unmasking [`RxIrq`].
pub fn init() {
    write(BAUDDIV, (CORE_HZ / BAUD).max(16));
    write(CTRL, CTRL_TX_EN | CTRL_RX_EN | CTRL_RX_INT);
}

/// The RX interrupt: masks its NVIC line (the byte stays in the UART) and wakes [`rx_task`].
pub fn on_rx_interrupt() {
    NVIC::mask(RxIrq);
    RX_READY.signal(());
}

/// Moves received bytes into [`LINK_RX`], with flow control (see the module documentation).
#[embassy_executor::task]
pub async fn rx_task() {
    let mut buf = [0u8; 64];
    loop {
        RX_READY.wait().await;
        loop {
            // Clear first: a byte that arrives after this flags the interrupt again.
            write(INTCLEAR, INT_RX | INT_RX_OVERRUN);
            let mut n = 0;
            let mut idle = 0;
            while n < buf.len() && idle < RX_SPIN {
                if read(STATE) & STATE_RX_FULL != 0 {
                    buf[n] = read(DATA) as u8;
                    n += 1;
                    idle = 0;
                } else {
                    idle += 1;
                }
            }
            if read(STATE) & STATE_RX_OVERRUN != 0 {
                write(STATE, STATE_RX_OVERRUN);
                count(&IO.link_rx_errors, 1);
            }
            if n == 0 {
                break;
            }
            count(&IO.link_rx_bytes, n as u32);
            LINK_RX.write_all(&buf[..n]).await;
        }
        // SAFETY: unmasking only re-enables this task's own wake-up; a byte that arrived since
        // the last clear raises the interrupt at once.
        unsafe { NVIC::unmask(RxIrq) };
    }
}

/// Sends the telemetry bytes queued in [`LINK_TX`].
#[embassy_executor::task]
pub async fn tx_task() {
    let mut buf = [0u8; 128];
    loop {
        let n = LINK_TX.read(&mut buf).await;
        for &b in &buf[..n] {
            while read(STATE) & STATE_TX_FULL != 0 {
                yield_now().await;
            }
            write(DATA, u32::from(b));
        }
    }
}
