//! The mission microservice on the vehicle's side: the messages it receives ([`MissionMessage`], from the
//! link), what it answers ([`MissionReply`]), and the upload in progress ([`Transfer`]): after
//! `MISSION_COUNT` the vehicle requests each item in turn with `MISSION_REQUEST_INT`, asks
//! again for an item that does not come within [`RETRY_US`] (at most [`RETRIES`] times, then the
//! upload is cancelled with `MAV_MISSION_OPERATION_CANCELLED`), and hands the complete list to
//! the pipeline, which certifies it before it answers `MISSION_ACK`
//! (<https://mavlink.io/en/services/mission.html>). Downloads need no state: each request is
//! answered from the stored mission.

use heapless::Vec;
use mavlink::dialects::common::MavMissionResult;

use super::CAPACITY;
use crate::link::MissionItem;
pub use crate::link::MissionMessage;
use crate::link::Sender;

/// An item not received this long after its request is requested again \[µs\].
pub const RETRY_US: u64 = 1_500_000;
/// Requests of one item before the upload is cancelled.
pub const RETRIES: u8 = 5;

/// A mission-protocol message from the vehicle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MissionReply {
    /// `MISSION_COUNT` to `to`.
    Count {
        /// Number of items.
        count: u16,
        /// Mission type.
        mission_type: u8,
        /// Addressee.
        to: Sender,
    },
    /// `MISSION_REQUEST_INT` for item `seq` to `to`.
    Request {
        /// Item number.
        seq: u16,
        /// Addressee.
        to: Sender,
    },
    /// `MISSION_ITEM_INT` number `seq` of the stored mission to `to`.
    Item {
        /// Item number.
        seq: u16,
        /// Addressee.
        to: Sender,
    },
    /// `MISSION_ACK` with `result` to `to`.
    Ack {
        /// Result.
        result: MavMissionResult,
        /// Mission type.
        mission_type: u8,
        /// Addressee.
        to: Sender,
    },
    /// `MISSION_CURRENT` (broadcast).
    Current {
        /// Current item.
        seq: u16,
    },
    /// `MISSION_ITEM_REACHED` (broadcast).
    Reached {
        /// Item reached.
        seq: u16,
    },
    /// `GPS_GLOBAL_ORIGIN` (broadcast): the origin now in force.
    Origin,
}

/// What an uploaded item leads to.
// The complete list is moved out once per upload, straight into the stored mission; no
// allocator to box it with.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq)]
pub enum UploadStep {
    /// Request item `seq` (the next one, or the expected one again after a duplicate or a
    /// skipped number).
    Request(u16),
    /// All items are in: certify them, then acknowledge.
    Complete(Vec<MissionItem, CAPACITY>),
    /// No upload from this sender is in progress: ignored.
    Ignored,
}

#[derive(Clone, Debug, PartialEq)]
struct Upload {
    partner: Sender,
    count: u16,
    items: Vec<MissionItem, CAPACITY>,
    requested_us: u64,
    retries: u8,
}

/// The upload in progress, if any.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Transfer {
    upload: Option<Upload>,
}

impl Transfer {
    /// No upload.
    pub const fn new() -> Self {
        Self { upload: None }
    }

    /// Whether an upload is in progress.
    pub fn uploading(&self) -> bool {
        self.upload.is_some()
    }

    /// `MISSION_COUNT` of `count` (1..=[`CAPACITY`], checked by the caller) from `from` at
    /// `now_us`: a new upload (replacing one in progress); the first request to send.
    pub fn begin(&mut self, from: Sender, count: u16, now_us: u64) -> u16 {
        self.upload = Some(Upload {
            partner: from,
            count,
            items: Vec::new(),
            requested_us: now_us,
            retries: 0,
        });
        0
    }

    /// Item `seq` from `from` at `now_us`.
    pub fn item(&mut self, from: Sender, seq: u16, item: MissionItem, now_us: u64) -> UploadStep {
        let Some(up) = self.upload.as_mut() else {
            return UploadStep::Ignored;
        };
        if up.partner != from {
            return UploadStep::Ignored;
        }
        let expected = up.items.len() as u16;
        if seq == expected && up.items.push(item).is_ok() {
            up.retries = 0;
            up.requested_us = now_us;
            if up.items.len() as u16 == up.count {
                let items = core::mem::take(&mut up.items);
                self.upload = None;
                return UploadStep::Complete(items);
            }
            return UploadStep::Request(expected + 1);
        }
        UploadStep::Request(expected)
    }

    /// At `now_us`: the item to request again when its request has gone unanswered for
    /// [`RETRY_US`], or `Err(partner)` when it has been requested [`RETRIES`] times (the upload
    /// is then dropped; answer `MAV_MISSION_OPERATION_CANCELLED`).
    pub fn poll(&mut self, now_us: u64) -> Option<Result<(u16, Sender), Sender>> {
        let up = self.upload.as_mut()?;
        if now_us.saturating_sub(up.requested_us) < RETRY_US {
            return None;
        }
        if up.retries >= RETRIES {
            let partner = up.partner;
            self.upload = None;
            return Some(Err(partner));
        }
        up.retries += 1;
        up.requested_us = now_us;
        Some(Ok((up.items.len() as u16, up.partner)))
    }

    /// Drops the upload in progress (the ground station cancelled it).
    pub fn cancel(&mut self, from: Sender) {
        if self.upload.as_ref().is_some_and(|u| u.partner == from) {
            self.upload = None;
        }
    }
}
