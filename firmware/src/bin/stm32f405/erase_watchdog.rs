//! The IWDG stretched around a flash sector erase (`firmware::erase_watchdog`): a 128 KiB sector
//! of the single-bank STM32F405 stalls the CPU for up to 4 s, the flight timeout is 50 ms.
//! embassy's `IndependentWatchdog` sets its timeout only when built, so this writes the
//! prescaler and reload registers itself (RM0090, section "Independent watchdog": key 0x5555
//! unlocks PR and RLR, PVU/RVU show an update in progress, key 0xAAAA reloads).

/// LSI frequency the timeouts are computed for \[Hz\] (nominal; embassy's `LSI_FREQ` for F4).
const LSI_NOMINAL_HZ: u32 = 32_000;
/// The fastest LSI of the STM32F405 datasheet (LSI characteristics, f_LSI max) \[Hz\].
const LSI_MAX_HZ: u32 = 47_000;
/// Longest 128 KiB sector erase of the STM32F405 datasheet (t_ERASE128KB, x8 parallelism) \[µs\].
const ERASE_MAX_US: u32 = 4_000_000;
/// The largest prescaler (/256, PR = 6).
const PRESCALER: u32 = 256;
const PR_DIVIDE_BY_256: u8 = 6;

/// The reload value for `timeout_us` at the nominal LSI with the /256 prescaler.
const fn erase_reload(timeout_us: u32) -> u16 {
    let ticks = (timeout_us as u64 * LSI_NOMINAL_HZ as u64 / PRESCALER as u64 / 1_000_000) as u32;
    let rl = ticks - 1;
    assert!(rl <= 0xFFF, "the IWDG reload register has 12 bits");
    rl as u16
}

/// The erase reload value (999 for 8 s).
const ERASE_RELOAD: u16 = erase_reload(firmware::erase_watchdog::ERASE_TIMEOUT_US);

/// Timeout of the erase setting at LSI frequency `lsi_hz` \[µs\].
const fn erase_timeout_us(lsi_hz: u32) -> u64 {
    (ERASE_RELOAD as u64 + 1) * PRESCALER as u64 * 1_000_000 / lsi_hz as u64
}

// Even the fastest LSI leaves the longest erase time to finish: checked when building.
const _: () = assert!(erase_timeout_us(LSI_MAX_HZ) > ERASE_MAX_US as u64);

#[cfg(target_os = "none")]
pub use mcu::IwdgStretch;

#[cfg(target_os = "none")]
mod mcu {
    use embassy_stm32::pac;
    use embassy_stm32::pac::iwdg::vals::{Key, Pr};
    use firmware::erase_watchdog::EraseWatchdog;

    use super::{ERASE_RELOAD, PR_DIVIDE_BY_256};

    /// Polls of the status register before giving up on an update (each a few cycles; an
    /// update takes at most 5 LSI periods, ~160 µs, i.e. ~27 000 cycles at 168 MHz).
    const UPDATE_POLLS: u32 = 200_000;

    /// The IWDG's prescaler and reload, stretched for an erase and put back after it.
    pub struct IwdgStretch {
        /// (PR, RLR) in force before `lengthen`.
        flight: Option<(Pr, u16)>,
    }

    impl IwdgStretch {
        /// Nothing stretched yet.
        pub const fn new() -> Self {
            Self { flight: None }
        }
    }

    /// Writes PR and RLR, waits for the update, reloads. The unlock and the writes are one
    /// critical section: a feed (key 0xAAAA) from the control interrupt in between would lock
    /// the registers again and the write would be lost.
    fn set(pr: Pr, rl: u16) {
        let iwdg = pac::IWDG;
        critical_section::with(|_| {
            iwdg.kr().write(|w| w.set_key(Key::ENABLE));
            iwdg.pr().write(|w| w.set_pr(pr));
            iwdg.rlr().write(|w| w.set_rl(rl));
        });
        // Only after the update does a reload load the new value. Bounded: a stuck update
        // leaves the old timeout, which resets the MCU at worst, as before this guard.
        for _ in 0..UPDATE_POLLS {
            let sr = iwdg.sr().read();
            if !sr.pvu() && !sr.rvu() {
                break;
            }
        }
        iwdg.kr().write(|w| w.set_key(Key::RESET));
    }

    impl EraseWatchdog for IwdgStretch {
        fn lengthen(&mut self) {
            let iwdg = pac::IWDG;
            self.flight = Some((iwdg.pr().read().pr(), iwdg.rlr().read().rl()));
            set(Pr::from_bits(PR_DIVIDE_BY_256), ERASE_RELOAD);
        }

        fn restore(&mut self) {
            if let Some((pr, rl)) = self.flight.take() {
                set(pr, rl);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The erase setting lasts the requested 8 s at the nominal LSI, and still more than the
    /// longest erase at the fastest LSI the datasheet allows.
    #[test]
    fn the_erase_timeout_outlasts_the_longest_erase() {
        let nominal = erase_timeout_us(LSI_NOMINAL_HZ);
        assert!(nominal >= u64::from(firmware::erase_watchdog::ERASE_TIMEOUT_US));
        assert!(nominal < 8_100_000, "{nominal}");
        assert!(erase_timeout_us(LSI_MAX_HZ) > u64::from(ERASE_MAX_US));
        assert_eq!(ERASE_RELOAD, 999);
    }
}
