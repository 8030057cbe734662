//! The parameter store's hold on arming. On a single-bank flash (the STM32F405's) a sector
//! erase stalls the CPU, control loop included, for up to seconds; a save can erase. So a board
//! that persists parameters ([`FlightPipeline::attach_storage`]) keeps the vehicle disarmed from
//! the accepted `PARAM_SET` (or storage reset) until its store reports the save done
//! ([`FlightPipeline::set_storage_busy`]): an arm meanwhile is answered
//! `TEMPORARILY_REJECTED` ("saving parameters"). Boards without a store (QEMU, SIL) arm as
//! before.

use super::FlightPipeline;

/// Whether a store is attached, and whether it has work pending or under way.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct StorageHold {
    attached: bool,
    busy: bool,
}

impl StorageHold {
    /// A parameter change was accepted: the store has work from now on (if there is a store).
    pub(super) fn changed(&mut self) {
        self.busy = self.attached;
    }

    /// Whether arming must wait.
    pub(super) fn busy(&self) -> bool {
        self.busy
    }
}

impl FlightPipeline {
    /// Declares that this board saves parameter changes to flash (at boot, once a store is
    /// open). From then on each accepted change holds arming until
    /// [`FlightPipeline::set_storage_busy`]`(false)`.
    pub fn attach_storage(&mut self) {
        self.storage.attached = true;
    }

    /// The store's state, from the board's store task: `true` from the request until the save
    /// (erase included) has finished, `false` once nothing is pending. Ignored without
    /// [`FlightPipeline::attach_storage`]. The pipeline also sets it itself the moment it
    /// accepts a change, so an arm in the same byte stream right after a `PARAM_SET` waits too.
    pub fn set_storage_busy(&mut self, busy: bool) {
        self.storage.busy = self.storage.attached && busy;
    }

    /// Whether arming waits for the parameter store.
    pub fn storage_busy(&self) -> bool {
        self.storage.busy()
    }
}
