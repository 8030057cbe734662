//! embassy-time driver on the Cortex-M SysTick: a 1 kHz interrupt counts milliseconds and wakes
//! the expired timers of an `embassy-time-queue-utils` queue.
//!
//! The tick rate is embassy-time's default 1 MHz: `now()` is the millisecond count × 1000 plus
//! the microseconds SysTick has counted since (so the control task times its steps to the
//! microsecond); timers fire at the first millisecond boundary at or after their deadline (at
//! most 1 ms late).
//! That is all the QEMU board needs: its control ticks follow the simulation's clock
//! ([`firmware::app::control::LockstepClock`]), and only the logger and the heartbeat use
//! embassy-time. SysTick is clocked by the core clock, 25 MHz on QEMU's `mps2-an386`.

use core::cell::{Cell, RefCell};
use core::sync::atomic::{AtomicBool, Ordering};
use core::task::Waker;

use cortex_m::peripheral::syst::SystClkSource;
use cortex_m::peripheral::{SCB, SYST};
use cortex_m_rt::exception;
use embassy_sync::blocking_mutex::raw::CriticalSectionRawMutex;
use embassy_sync::blocking_mutex::Mutex;
use embassy_time_driver::Driver;
use embassy_time_queue_utils::Queue;

/// Core clock of QEMU's `mps2-an386` \[Hz\] (its `SYSCLK`; QEMU 7.2 `hw/arm/mps2.c`).
pub const CORE_HZ: u32 = 25_000_000;

/// Microseconds per SysTick interrupt.
const TICK_US: u64 = 1_000;

/// SysTick reload value: the counter runs from it down to 0 once per millisecond.
const RELOAD: u32 = CORE_HZ / 1_000 - 1;

/// Set by [`init`] once the counter runs.
static STARTED: AtomicBool = AtomicBool::new(false);

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
        self.now_us.lock(|t| {
            // Inside the critical section the SysTick handler cannot run: a reload since its
            // last run shows as the pending flag. Read the counter on both sides of the flag so
            // that the value used belongs to the same millisecond as the count it is added to.
            let before = SYST::get_current();
            let wrapped = SCB::is_pendst_pending();
            let after = SYST::get_current();
            // Before `init` the counter means nothing.
            if !STARTED.load(Ordering::Relaxed) {
                return t.get();
            }
            // QEMU's SysTick reads 0 twice around a reload, meaning opposite things (its
            // ptimer's wrap-after-one-period policy): with the flag raised, for one count right
            // after the reload, before the counter shows RELOAD: the start of the new
            // millisecond; without it, from the expiry until the timer raises the flag: the end
            // of the millisecond, 999 µs, except before the first reload, where the counter has
            // not been loaded yet. Read as "999 µs into the new millisecond", the first made
            // the clock jump 1 ms ahead and back (a boot self-check saw it at one reload in
            // three) and the step that ended on it an overrun.
            let (ms_us, counted) = if wrapped {
                let counted = if after == 0 { 0 } else { RELOAD - after };
                (t.get() + TICK_US, counted)
            } else if before == 0 {
                let ms = t.get();
                (ms, if ms == 0 { 0 } else { RELOAD })
            } else {
                (t.get(), RELOAD.saturating_sub(before))
            };
            ms_us + u64::from(counted) / u64::from(CORE_HZ / 1_000_000)
        })
    }

    fn schedule_wake(&self, at: u64, waker: &Waker) {
        // Expired timers are woken by the next SysTick interrupt, within 1 ms: no alarm to
        // reprogram, so the "next expiration changed" answer is not needed.
        self.queue.lock(|q| {
            q.borrow_mut().schedule_wake(at, waker);
        });
    }
}

/// What [`self_check`] saw.
pub struct ClockCheck {
    /// `now()` readings taken.
    pub reads: u32,
    /// Readings earlier than the one before.
    pub backwards: u32,
    /// Readings more than [`JUMP_US`] after the one before (a few instructions apart, so only a
    /// miscomposed millisecond count can do that).
    pub jumps: u32,
    /// The largest step between two consecutive readings \[µs\].
    pub max_step_us: u64,
}

/// Readings after which [`self_check`] stops whatever the clock says.
const READS_MAX: u32 = 10_000_000;

/// A step between consecutive [`self_check`] readings above this \[µs\] is a jump.
pub const JUMP_US: u64 = 100;

/// Reads `now()` back to back for `span_us` of its own time and counts readings that go back
/// or jump ahead: the millisecond count and the SysTick counter must compose into one
/// monotonic clock across every reload, or the control task's step times (and its overruns)
/// are wrong by a millisecond.
pub fn self_check(span_us: u64) -> ClockCheck {
    let start = DRIVER.now();
    let mut prev = start;
    let mut c = ClockCheck {
        reads: 0,
        backwards: 0,
        jumps: 0,
        max_step_us: 0,
    };
    // A clock stuck below `start` still ends the check: at most READS_MAX readings.
    while prev.saturating_sub(start) < span_us && c.reads < READS_MAX {
        let t = DRIVER.now();
        c.reads += 1;
        if t < prev {
            c.backwards += 1;
        } else {
            let step = t - prev;
            c.max_step_us = c.max_step_us.max(step);
            if step > JUMP_US {
                c.jumps += 1;
            }
        }
        prev = t;
    }
    c
}

/// Starts the 1 kHz SysTick interrupt.
pub fn init(mut syst: SYST) {
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload(RELOAD);
    syst.clear_current();
    syst.enable_interrupt();
    syst.enable_counter();
    STARTED.store(true, Ordering::Relaxed);
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
