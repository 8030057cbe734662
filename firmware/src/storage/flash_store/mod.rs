//! The parameters persisted on NOR flash: one record holding the whole table, in a
//! `sequential-storage` map ([`FlashStore`]), restored at boot through
//! [`crate::pipeline::FlightPipeline::restore_params`] ([`FlashStore::restore`]).
//!
//! Integrity, in layers:
//! - sequential-storage checks every item: a CRC-32 over its data and a CRC-16 over its length;
//!   an item that fails is skipped, so a fetch returns the newest intact record. Its page
//!   markers make a cut erase or migration detectable (`Corrupted`, which it repairs).
//! - The record carries [`FORMAT`] and [`TABLE_HASH`] (names, units and ranges of
//!   [`PARAMS`]) and has an exact length: values stored by a build with another table are
//!   ignored, never applied to the wrong parameter.
//! - The values then pass every check of a `PARAM_SET` (range, orderings, certificate, box fit)
//!   all at once, or none is taken.
//!
//! The whole table is one item, written in one `store_item`: a power cut mid-write leaves the
//! previous record (the new one fails its CRC) or the new one, never a mix of the two sets.
//! Whatever fails, the vehicle flies the build's flight file and the store is erased, so the
//! next boot does not meet the same damage. A record of the header alone ([`FlashStore::clear`])
//! means "nothing stored": a reset to the flight file without an erase.

use embedded_storage_async::nor_flash::NorFlash;
use sequential_storage::cache::{Cache, Uncached};
use sequential_storage::map::{MapConfig, MapConfigError, MapStorage};
use sequential_storage::Error;

use crate::config::FlightConfig;
use crate::param_store::{MemoryStore, ParamStore};
use crate::params::{COUNT, PARAMS};
use crate::pipeline::{FlightPipeline, ParamRefusal, RestoreError};

/// Version of the record layout below; a change makes older records ignored.
pub const FORMAT: u32 = 1;

/// FNV-1a (32 bit) over every parameter's name, unit and range bits, in table order: a build
/// with another table (a parameter added, moved, renamed or re-ranged) computes another hash.
pub const TABLE_HASH: u32 = table_hash();

/// The map key of the parameter record (the map holds nothing else).
const KEY: u8 = b'P';

/// Record: [`FORMAT`] (u32 LE), [`TABLE_HASH`] (u32 LE), then one f32 LE per parameter in
/// [`PARAMS`] order and units \[bytes\].
pub const RECORD_LEN: usize = HEADER_LEN + 4 * COUNT;

/// A record of the header alone says "nothing stored" ([`FlashStore::clear`]) \[bytes\].
pub const HEADER_LEN: usize = 8;

/// Scratch for sequential-storage: key + record, rounded up to any flash word (≤ 32 bytes).
const BUF_LEN: usize = (1 + RECORD_LEN).div_ceil(32) * 32;

const fn fnv(mut h: u32, bytes: &[u8]) -> u32 {
    let mut i = 0;
    while i < bytes.len() {
        h = (h ^ bytes[i] as u32).wrapping_mul(0x0100_0193);
        i += 1;
    }
    h
}

const fn table_hash() -> u32 {
    let mut h = 0x811c_9dc5;
    let mut i = 0;
    while i < PARAMS.len() {
        let p = &PARAMS[i];
        h = fnv(h, p.name.as_bytes());
        // Separators: ("AB", "C") and ("A", "BC") must differ.
        h = fnv(h, &[0]);
        h = fnv(h, p.unit.as_bytes());
        h = fnv(h, &[0]);
        h = fnv(h, &p.min.to_bits().to_le_bytes());
        h = fnv(h, &p.max.to_bits().to_le_bytes());
        i += 1;
    }
    h
}

/// Some flash (the STM32's) wants write buffers word-aligned in RAM.
#[repr(C, align(32))]
struct Buffer([u8; BUF_LEN]);

/// Why the stored parameters were not taken.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Fault {
    /// The flash driver failed (read, write or erase error).
    Unreadable,
    /// The region is written but holds no intact record, or sequential-storage found its page
    /// markers inconsistent and could not repair them.
    Corrupt,
    /// An intact record of another layout or parameter table ([`FORMAT`], [`TABLE_HASH`],
    /// length).
    OtherTable,
    /// The values were refused as a whole by the pipeline's checks.
    Refused(RestoreError),
}

/// What [`FlashStore::restore`] did at boot.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Restore {
    /// Nothing stored (blank or cleared region): the build's flight file.
    Empty,
    /// The stored set was certified and is flown: `values` parameters taken.
    Restored {
        /// How many parameters were taken (the whole table).
        values: usize,
    },
    /// The stored set was not taken: the build's flight file is flown. `erased`: the region
    /// was erased so the next boot starts clean (false: the erase failed too).
    Defaults {
        /// Why.
        fault: Fault,
        /// Whether the region is now blank.
        erased: bool,
    },
}

/// The parameter record in a `sequential-storage` map on `S`, in the flash range given to
/// [`FlashStore::new`] (at least two erase pages; the store touches nothing outside it).
pub struct FlashStore<S: NorFlash> {
    map: MapStorage<u8, S, Cache<Uncached, Uncached, Uncached, u8>>,
    buf: Buffer,
}

impl<S: NorFlash> FlashStore<S> {
    /// The store on `range` (byte addresses of `flash`). Errors: the range is not whole erase
    /// pages, or fewer than two.
    pub fn new(flash: S, range: core::ops::Range<u32>) -> Result<Self, MapConfigError> {
        Ok(Self {
            map: MapStorage::new(flash, MapConfig::try_new(range)?, Cache::new_uncached()),
            buf: Buffer([0; BUF_LEN]),
        })
    }

    /// The flash back (tests, or to hand the driver to something else).
    pub fn into_flash(self) -> S {
        self.map.destroy().0
    }

    /// The stored values as a [`ParamStore`] (every parameter, or none: `Ok(None)` on a blank
    /// or cleared region). Errors: [`Fault`] (never `Refused`: nothing is checked against the
    /// set-up here).
    pub async fn load(&mut self) -> Result<Option<MemoryStore>, Fault> {
        let fetched = self.map.fetch_item::<&[u8]>(&mut self.buf.0, &KEY).await;
        match fetched {
            Ok(Some(bytes)) => decode(bytes),
            Ok(None) => match self.blank().await {
                Ok(true) => Ok(None),
                // Written, yet no intact record: every one failed its CRC.
                Ok(false) => Err(Fault::Corrupt),
                Err(()) => Err(Fault::Unreadable),
            },
            Err(Error::Corrupted { .. }) => Err(Fault::Corrupt),
            Err(_) => Err(Fault::Unreadable),
        }
    }

    /// Writes every parameter of `config` as one record (call it after an accepted
    /// `PARAM_SET`, [`crate::pipeline::Event::ParamChanged`], outside the control step: it
    /// may erase a page). Errors: sequential-storage's (the flash driver's, or a full store).
    pub async fn save(&mut self, config: &FlightConfig) -> Result<(), Error<S::Error>> {
        let mut record = [0u8; RECORD_LEN];
        record[..4].copy_from_slice(&FORMAT.to_le_bytes());
        record[4..8].copy_from_slice(&TABLE_HASH.to_le_bytes());
        for (p, slot) in PARAMS.iter().zip(record[8..].chunks_exact_mut(4)) {
            slot.copy_from_slice(&(p.get)(config).to_le_bytes());
        }
        self.map
            .store_item(&mut self.buf.0, &KEY, &&record[..])
            .await
    }

    /// Forgets the stored set with one record write (no erase, so it does not stall a
    /// single-bank flash for seconds): the next boot flies the build's flight file
    /// (`MAV_CMD_PREFLIGHT_STORAGE` reset). Errors: as [`FlashStore::save`].
    pub async fn clear(&mut self) -> Result<(), Error<S::Error>> {
        let mut record = [0u8; HEADER_LEN];
        record[..4].copy_from_slice(&FORMAT.to_le_bytes());
        record[4..].copy_from_slice(&TABLE_HASH.to_le_bytes());
        self.map
            .store_item(&mut self.buf.0, &KEY, &&record[..])
            .await
    }

    /// Erases the whole region (recovery at boot; a sector erase may take seconds): the next
    /// boot flies the build's flight file. Errors: the flash driver's.
    pub async fn erase(&mut self) -> Result<(), Error<S::Error>> {
        self.map.erase_all().await
    }

    /// At boot, disarmed, before the control loop: takes the stored set into `pipeline` if it
    /// is intact, of this build's table and certified; otherwise leaves the pipeline on the
    /// build's flight file and erases the region (not when the pipeline is armed: then
    /// nothing changes). The caller logs the outcome.
    pub async fn restore(&mut self, pipeline: &mut FlightPipeline) -> Restore {
        let fault = match self.load().await {
            Ok(None) => return Restore::Empty,
            Ok(Some(image)) => match pipeline.restore_params(&image) {
                Ok(values) => return Restore::Restored { values },
                Err(e) if e.refusal == ParamRefusal::Armed => {
                    return Restore::Defaults {
                        fault: Fault::Refused(e),
                        erased: false,
                    }
                }
                Err(e) => Fault::Refused(e),
            },
            Err(f) => f,
        };
        let erased = self.erase().await.is_ok();
        Restore::Defaults { fault, erased }
    }

    /// Whether the whole region reads erased (0xFF). `Err` on a read error.
    async fn blank(&mut self) -> Result<bool, ()> {
        let range = self.map.flash_range();
        // A multiple of any read size (a power of two ≤ 32).
        let mut chunk = [0u8; 32];
        let mut at = range.start;
        while at < range.end {
            let n = (range.end - at).min(chunk.len() as u32);
            let part = &mut chunk[..n as usize];
            self.map.flash().read(at, part).await.map_err(|_| ())?;
            if part.iter().any(|&b| b != 0xFF) {
                return Ok(false);
            }
            at += n;
        }
        Ok(true)
    }
}

/// The values of a record of this build's layout and table (`None`: a cleared store).
/// Errors: [`Fault::OtherTable`].
fn decode(bytes: &[u8]) -> Result<Option<MemoryStore>, Fault> {
    let word = |at: usize| -> Option<[u8; 4]> { bytes.get(at..at + 4)?.try_into().ok() };
    let header = |at| word(at).map(u32::from_le_bytes);
    if header(0) != Some(FORMAT) || header(4) != Some(TABLE_HASH) {
        return Err(Fault::OtherTable);
    }
    match bytes.len() {
        HEADER_LEN => return Ok(None),
        RECORD_LEN => {}
        _ => return Err(Fault::OtherTable),
    }
    let mut store = MemoryStore::new();
    for i in 0..COUNT {
        let v = word(HEADER_LEN + 4 * i).ok_or(Fault::OtherTable)?;
        // Range and finiteness are the pipeline's to check: it names the parameter refused.
        store
            .store(i, f32::from_le_bytes(v))
            .map_err(|_| Fault::OtherTable)?;
    }
    Ok(Some(store))
}

#[cfg(test)]
mod tests;
