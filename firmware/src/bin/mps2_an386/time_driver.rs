//! embassy-time driver on the Cortex-M SysTick: a 1 kHz interrupt counts milliseconds and wakes
//! the expired timers of an `embassy-time-queue-utils` queue.
//!
//! The tick rate is embassy-time's default 1 MHz, so `now()` is the millisecond count × 1000:
//! timers fire at the first millisecond boundary at or after their deadline (at most 1 ms late).
//! That is all the QEMU board needs: its control ticks follow the simulation's clock
//! ([`firmware::app::control::LockstepClock`]), and only the logger and the heartbeat use
//! embassy-time. SysTick is clocked by the core clock, 25 MHz on QEMU's `mps2-an386`.

use core::cell::{Cell, RefCell};
use core::task::Waker;

use cortex_m::peripheral::syst::SystClkSource;
use cortex_m::peripheral::SYST;
use cortex_m_rt::exception;
use embassy_sync::blocking_mutex::raw::CriticalSectionRawMutex;
use embassy_sync::blocking_mutex::Mutex;
use embassy_time_driver::Driver;
use embassy_time_queue_utils::Queue;

/// Core clock of QEMU's `mps2-an386` \[Hz\] (its `SYSCLK`; QEMU 7.2 `hw/arm/mps2.c`).
pub const CORE_HZ: u32 = 25_000_000;

/// Microseconds per SysTick interrupt.
const TICK_US: u64 = 1_000;

struct SysTickDriver {
    now_us: Mutex<CriticalSectionRawMutex, Cell<u64>>,
    queue: Mutex<CriticalSectionRawMutex, RefCell<Queue>>,
}

embassy_time_driver::time_driver_impl!(static DRIVER: SysTickDriver = SysTickDriver {
    now_us: Mutex::new(Cell::new(0)),
    queue: Mutex::new(RefCell::new(Queue::new())),
});

impl Driver for SysTickDriver {
    fn now(&self) -> u64 {
        self.now_us.lock(|t| t.get())
    }

    fn schedule_wake(&self, at: u64, waker: &Waker) {
        // Expired timers are woken by the next SysTick interrupt, within 1 ms: no alarm to
        // reprogram, so the "next expiration changed" answer is not needed.
        self.queue.lock(|q| {
            q.borrow_mut().schedule_wake(at, waker);
        });
    }
}

/// Starts the 1 kHz SysTick interrupt.
pub fn init(mut syst: SYST) {
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload(CORE_HZ / 1_000 - 1);
    syst.clear_current();
    syst.enable_interrupt();
    syst.enable_counter();
}

#[exception]
fn SysTick() {
    let now = DRIVER.now_us.lock(|t| {
        let now = t.get() + TICK_US;
        t.set(now);
        now
    });
    DRIVER.queue.lock(|q| {
        q.borrow_mut().next_expiration(now);
    });
}
