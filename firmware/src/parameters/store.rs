//! What [`crate::pipeline::FlightPipeline::restore_params`] restores from: the [`ParamStore`]
//! interface, an in-memory implementation ([`MemoryStore`]) and [`save`]. On flash,
//! [`crate::flash_store::FlashStore`] keeps the whole table as one record and decodes it into
//! a [`MemoryStore`].
//!
//! Stored values are never trusted: [`crate::pipeline::FlightPipeline::restore_params`] applies
//! them all at once to a candidate set-up and takes it only if it passes the checks of a
//! `PARAM_SET` (range, orderings, certificate and box fit), so a store written by another build
//! or damaged cannot make the vehicle fly an uncertified set-up.

use crate::config::FlightConfig;
use crate::params::{COUNT, PARAMS};

/// Storage of parameter values, by index in [`PARAMS`], in the table's units.
pub trait ParamStore {
    /// The medium's error (a flash write failing, …).
    type Error;

    /// The stored value of parameter `index`, if one is stored (`None` also for an index
    /// beyond the table).
    fn load(&self, index: usize) -> Option<f32>;

    /// Stores `value` for parameter `index`. Errors: the medium's, or an index beyond the
    /// table (the implementation's to report).
    fn store(&mut self, index: usize, value: f32) -> Result<(), Self::Error>;
}

/// A [`ParamStore`] in RAM (tests, and a flash record once decoded): one slot per parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MemoryStore {
    values: [Option<f32>; COUNT],
}

/// [`MemoryStore::store`] at an index beyond the table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NoSuchParam;

impl MemoryStore {
    /// Nothing stored.
    pub const fn new() -> Self {
        Self {
            values: [None; COUNT],
        }
    }
}

impl Default for MemoryStore {
    fn default() -> Self {
        Self::new()
    }
}

impl ParamStore for MemoryStore {
    type Error = NoSuchParam;

    fn load(&self, index: usize) -> Option<f32> {
        self.values.get(index).copied().flatten()
    }

    fn store(&mut self, index: usize, value: f32) -> Result<(), NoSuchParam> {
        let slot = self.values.get_mut(index).ok_or(NoSuchParam)?;
        *slot = Some(value);
        Ok(())
    }
}

/// Stores every parameter of `config` (call it after an accepted `PARAM_SET`,
/// [`crate::pipeline::Event::ParamChanged`]). Stops at the first error, which it returns.
pub fn save<S: ParamStore>(store: &mut S, config: &FlightConfig) -> Result<(), S::Error> {
    for (i, p) in PARAMS.iter().enumerate() {
        store.store(i, (p.get)(config))?;
    }
    Ok(())
}
