//! Where the STM32F405 keeps its parameters: the last two 128 KiB sectors of its flash (10 and
//! 11, 0x080C_0000..0x0810_0000), which the program never occupies (`boards/stm32f405/
//! memory.x` ends FLASH at 768 KiB; the size budget is 384 KiB). Two sectors: sequential-
//! storage needs a spare page to migrate into. Sector erases stall the CPU (single bank) for
//! up to seconds: only the boot restore and a save whose page is full erase, each under a
//! lengthened watchdog (`erase_watchdog.rs`), and only while disarmed (the pipeline holds
//! arming until a save is done); see docs/mavlink.md.

use core::ops::Range;

use embassy_stm32::flash::{Async, Bank1Region3, Flash};
use embassy_stm32::peripherals::FLASH;
use embassy_stm32::Peri;
use firmware::erase_watchdog::EraseGuarded;
use firmware::flash_store::FlashStore;

use crate::erase_watchdog::IwdgStretch;

use crate::pins::hw::Irqs;

/// The store's flash: region 3 of bank 1 (sectors 5 to 11, 128 KiB each, from 0x0802_0000),
/// its erases under the lengthened watchdog.
pub type Store = FlashStore<EraseGuarded<Bank1Region3<'static, Async>, IwdgStretch>>;

/// Region 3's base address.
const REGION_BASE: u32 = 0x0802_0000;
/// Sector 10's address: the store's start.
const STORE_START: u32 = 0x080C_0000;
/// The end of the flash (1 MiB).
const FLASH_END: u32 = 0x0810_0000;

/// The store's bytes as offsets in region 3.
const RANGE: Range<u32> = (STORE_START - REGION_BASE)..(FLASH_END - REGION_BASE);

/// The store on sectors 10 and 11; `None` if sequential-storage refuses the range (it cannot:
/// whole 128 KiB pages, two of them).
pub fn open(flash: Peri<'static, FLASH>) -> Option<Store> {
    let regions = Flash::new(flash, Irqs).into_regions();
    FlashStore::new(
        EraseGuarded::new(regions.bank1_region3, IwdgStretch::new()),
        RANGE,
    )
    .ok()
}
