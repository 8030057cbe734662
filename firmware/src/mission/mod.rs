//! Missions uploaded over MAVLink's mission microservice: the stored items
//! ([`MissionItem`], in [`crate::link`] with the messages that carry them), what the
//! vehicle makes of them, a certified reference through their stops ([`mod@plan`]), and the upload
//! state ([`transfer`]). The pipeline runs the protocol and flies the plan
//! (`crate::pipeline`'s `mission_protocol.rs` and `mission_flight.rs`).
//!
//! Capacity: [`CAPACITY`] items, about 1.2 KiB for the stored mission plus as much for an upload
//! in progress (an upload replaces the stored mission only once it is complete and certified,
//! so a failed or refused upload loses nothing). A longer mission is refused with
//! `MAV_MISSION_NO_SPACE`.

pub mod origin;
pub mod plan;
#[cfg(test)]
mod tests;
pub mod transfer;

pub use crate::link::{MissionItem, MissionMessage};
pub use origin::GlobalOrigin;
pub use plan::{plan, GlobalFrame, Plan, PlanError};
pub use transfer::{MissionReply, Transfer, UploadStep};

/// Largest number of items a mission may have.
pub const CAPACITY: usize = 32;

/// `MAV_MISSION_TYPE_MISSION`: the flight plan (the only type stored; fences and rally points
/// are answered as empty and refused on upload).
pub const MISSION_TYPE_MISSION: u8 = 0;
/// `MAV_MISSION_TYPE_ALL`: clearing every type.
pub const MISSION_TYPE_ALL: u8 = 255;
