//! Sector erases under a lengthened watchdog ([`EraseGuarded`]). On a single-bank flash (the
//! STM32F405's) the CPU cannot fetch an instruction while a sector erases: a 128 KiB sector
//! takes 1-2 s at 32-bit parallelism, up to 4 s at 8-bit (STM32F405 datasheet, flash
//! characteristics, t_ERASE128KB), while the flight watchdog resets the MCU after 50 ms
//! without a control step. [`EraseGuarded`] wraps the store's flash so that each erase runs
//! with the watchdog lengthened ([`EraseWatchdog::lengthen`]) and the flight timeout is back
//! ([`EraseWatchdog::restore`]) the moment it ends, failed or not. Reads and word writes (tens
//! of µs) pass through unchanged. Erases happen only while disarmed: the pipeline holds arming
//! while a save is pending ([`crate::pipeline::FlightPipeline::attach_storage`]).

use embedded_storage_async::nor_flash::{ErrorType, NorFlash, ReadNorFlash};

/// Timeout the watchdog must allow during an erase \[µs\]: twice the longest 128 KiB sector
/// erase at any parallelism (4 s, STM32F405 datasheet), so that even a fast LSI (47 kHz for a
/// 32 kHz nominal) leaves more than the erase.
pub const ERASE_TIMEOUT_US: u32 = 8_000_000;

/// A watchdog whose timeout can be stretched for an erase and put back.
pub trait EraseWatchdog {
    /// Sets the timeout to at least [`ERASE_TIMEOUT_US`] and reloads the counter.
    fn lengthen(&mut self);
    /// Puts the timeout in force before [`EraseWatchdog::lengthen`] back and reloads the
    /// counter.
    fn restore(&mut self);
}

/// `flash` whose erases run under `watchdog`'s lengthened timeout; everything else passes
/// through. Errors: the wrapped flash's, unchanged.
pub struct EraseGuarded<F, W> {
    flash: F,
    watchdog: W,
}

impl<F, W> EraseGuarded<F, W> {
    /// Wraps `flash`; `watchdog` is lengthened around each erase.
    pub fn new(flash: F, watchdog: W) -> Self {
        Self { flash, watchdog }
    }

    /// The wrapped flash and watchdog.
    pub fn into_parts(self) -> (F, W) {
        (self.flash, self.watchdog)
    }
}

impl<F: ErrorType, W> ErrorType for EraseGuarded<F, W> {
    type Error = F::Error;
}

impl<F: ReadNorFlash, W> ReadNorFlash for EraseGuarded<F, W> {
    const READ_SIZE: usize = F::READ_SIZE;

    async fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), Self::Error> {
        self.flash.read(offset, bytes).await
    }

    fn capacity(&self) -> usize {
        self.flash.capacity()
    }
}

impl<F: NorFlash, W: EraseWatchdog> NorFlash for EraseGuarded<F, W> {
    const WRITE_SIZE: usize = F::WRITE_SIZE;
    const ERASE_SIZE: usize = F::ERASE_SIZE;

    async fn erase(&mut self, from: u32, to: u32) -> Result<(), Self::Error> {
        self.watchdog.lengthen();
        let result = self.flash.erase(from, to).await;
        self.watchdog.restore();
        result
    }

    async fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), Self::Error> {
        self.flash.write(offset, bytes).await
    }
}

#[cfg(test)]
mod tests {
    //! The guard against sequential-storage's RAM model of a NOR flash, driven by the real
    //! parameter store: every erase runs lengthened, nothing else does, and a failed erase
    //! still restores the flight timeout. Given/when/then.
    use core::cell::Cell;

    use embassy_futures::block_on;
    use sequential_storage::mock_flash::{MockFlashBase, WriteCountCheck};

    use super::*;
    use crate::config::FlightConfig;
    use crate::flash_store::FlashStore;

    type Mock = MockFlashBase<4, 4, 128>;

    /// What the flash saw: erases with the watchdog lengthened or not, writes while lengthened.
    #[derive(Default)]
    struct Probe {
        lengthened: Cell<bool>,
        lengthens: Cell<u32>,
        restores: Cell<u32>,
        covered_erases: Cell<u32>,
        bare_erases: Cell<u32>,
        writes_while_lengthened: Cell<u32>,
    }

    fn bump(c: &Cell<u32>) {
        c.set(c.get() + 1);
    }

    struct ProbedFlash<'a> {
        mock: Mock,
        probe: &'a Probe,
    }

    impl ErrorType for ProbedFlash<'_> {
        type Error = <Mock as ErrorType>::Error;
    }

    impl ReadNorFlash for ProbedFlash<'_> {
        const READ_SIZE: usize = Mock::READ_SIZE;
        async fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), Self::Error> {
            self.mock.read(offset, bytes).await
        }
        fn capacity(&self) -> usize {
            self.mock.capacity()
        }
    }

    impl NorFlash for ProbedFlash<'_> {
        const WRITE_SIZE: usize = Mock::WRITE_SIZE;
        const ERASE_SIZE: usize = Mock::ERASE_SIZE;
        async fn erase(&mut self, from: u32, to: u32) -> Result<(), Self::Error> {
            bump(if self.probe.lengthened.get() {
                &self.probe.covered_erases
            } else {
                &self.probe.bare_erases
            });
            self.mock.erase(from, to).await
        }
        async fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), Self::Error> {
            if self.probe.lengthened.get() {
                bump(&self.probe.writes_while_lengthened);
            }
            self.mock.write(offset, bytes).await
        }
    }

    struct ProbedWatchdog<'a>(&'a Probe);

    impl EraseWatchdog for ProbedWatchdog<'_> {
        fn lengthen(&mut self) {
            assert!(!self.0.lengthened.get(), "lengthened twice");
            self.0.lengthened.set(true);
            bump(&self.0.lengthens);
        }
        fn restore(&mut self) {
            assert!(self.0.lengthened.get(), "restored without lengthening");
            self.0.lengthened.set(false);
            bump(&self.0.restores);
        }
    }

    fn guarded(
        probe: &Probe,
        shutoff: Option<u32>,
    ) -> EraseGuarded<ProbedFlash<'_>, ProbedWatchdog<'_>> {
        let mock = Mock::new(WriteCountCheck::OnceOnly, shutoff, true);
        EraseGuarded::new(ProbedFlash { mock, probe }, ProbedWatchdog(probe))
    }

    /// Given the parameter store on a guarded flash, when it saves parameter sets until its
    /// pages fill and it migrates (erases), then every erase ran with the watchdog lengthened,
    /// the flight timeout came back after each, and no word write was lengthened.
    #[test]
    fn every_erase_of_a_save_runs_lengthened() {
        let probe = Probe::default();
        let flash = guarded(&probe, None);
        let mut store = FlashStore::new(flash, Mock::FULL_FLASH_RANGE).unwrap();
        let mut c = FlightConfig::built();
        for k in 0..40 {
            c.gains.position.kf *= if k % 2 == 0 { 0.99 } else { 1.0 / 0.99 };
            block_on(store.save(&c)).unwrap();
        }
        assert!(probe.covered_erases.get() > 0, "the saves never erased");
        assert_eq!(probe.bare_erases.get(), 0);
        assert_eq!(probe.lengthens.get(), probe.covered_erases.get());
        assert_eq!(probe.restores.get(), probe.lengthens.get());
        assert!(!probe.lengthened.get());
        assert_eq!(probe.writes_while_lengthened.get(), 0);
    }

    /// Given a guarded flash that fails (a power cut) in the middle of an erase, when the erase
    /// is asked, then the error comes back unchanged and the flight timeout is restored.
    #[test]
    fn a_failed_erase_still_restores_the_flight_timeout() {
        let probe = Probe::default();
        let mut flash = guarded(&probe, Some(100));
        let erase_size = <Mock as NorFlash>::ERASE_SIZE as u32;
        let r = block_on(flash.erase(0, erase_size));
        assert!(r.is_err(), "the model's power cut did not happen");
        assert_eq!((probe.lengthens.get(), probe.restores.get()), (1, 1));
        assert!(!probe.lengthened.get());
    }
}
