//! The parameter store on a board's flash ([`FlashStore`]): restored at boot, before the
//! control task starts, with the outcome and the restored certificate in the boot log; saved
//! by a low-priority task after each accepted `PARAM_SET` ([`PARAM_SAVE`]).

use core::sync::atomic::Ordering;

use defmt::{info, warn};
use embedded_storage_async::nor_flash::NorFlash;

use super::boot_log;
use super::queues::{ParamSave, PARAM_SAVE, STORAGE_BUSY};
use crate::flash_store::{Fault, FlashStore, Restore};
use crate::pipeline::{FlightPipeline, ParamRefusal, RestoreError};

/// Restores `pipeline` (disarmed, at boot) from `store` and logs the outcome; a restored set's
/// boot report (certificate, box fit) is logged again, since it replaces the banner's.
/// Blocking: it runs before the control task and the watchdog, so an erase (up to seconds on a
/// 128 KiB sector) delays nothing that flies.
pub fn restore<S: NorFlash>(store: &mut FlashStore<S>, pipeline: &mut FlightPipeline) {
    match embassy_futures::block_on(store.restore(pipeline)) {
        Restore::Empty => info!("params: nothing stored, flying the flight file"),
        Restore::Restored { values } => {
            info!(
                "params: {=usize} values restored from flash (certified)",
                values
            );
            boot_log::log_boot_report(&pipeline.boot_report());
        }
        Restore::Defaults { fault, erased } => {
            let why = match fault {
                Fault::Unreadable => "flash error",
                Fault::Corrupt => "corrupted",
                Fault::OtherTable => "another build's table",
                // The parameter refused on its own, or the failed condition.
                Fault::Refused(RestoreError { name: Some(n), .. }) => n,
                Fault::Refused(RestoreError {
                    refusal: ParamRefusal::Condition(f),
                    ..
                }) => f.condition,
                Fault::Refused(_) => "refused",
            };
            warn!(
                "params: stored set refused ({=str}), flying the flight file; store erased: {=bool}",
                why, erased
            );
        }
    }
}

/// Saves every accepted parameter set, or clears the store on a reset (the newest request,
/// [`PARAM_SAVE`]). Thread mode, lowest priority: the control task only signals. A failure is
/// logged; the set in force is unchanged and the next request is tried again. Clears
/// [`STORAGE_BUSY`] (arming held) once no request is left.
pub async fn run<S: NorFlash>(mut store: FlashStore<S>) -> ! {
    loop {
        match PARAM_SAVE.wait().await {
            ParamSave::Set(config) => match store.save(&config).await {
                Ok(()) => info!("params: saved to flash"),
                Err(_) => warn!("params: save to flash failed; a reset flies the previous set"),
            },
            ParamSave::Clear => match store.clear().await {
                Ok(()) => info!("params: store cleared; a reset flies the flight file"),
                Err(_) => warn!("params: clear failed; a reset restores the stored set"),
            },
        }
        // Masked, so that no request can come between the test and the store: a request
        // signalled meanwhile keeps the store busy (and arming held) until it is saved too.
        critical_section::with(|_| {
            if !PARAM_SAVE.signaled() {
                STORAGE_BUSY.store(false, Ordering::Release);
            }
        });
    }
}
