//! The mission microservice's messages as the vehicle receives them (addressing already
//! checked; [`super::Inbound::Mission`]); `crate::mission` answers them.

use super::mission_item::MissionItem;

/// A mission-protocol message for the vehicle (addressing already checked). `mission_type` is
/// the MAVLink 2 extension field (`MAV_MISSION_TYPE`, 0 when absent).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MissionMessage {
    /// `MISSION_REQUEST_LIST`: start a download.
    RequestList {
        /// Mission type.
        mission_type: u8,
    },
    /// `MISSION_REQUEST_INT` or `MISSION_REQUEST`: send item `seq`.
    Request {
        /// Item number.
        seq: u16,
        /// Mission type.
        mission_type: u8,
    },
    /// `MISSION_COUNT`: start an upload of `count` items.
    Count {
        /// Number of items.
        count: u16,
        /// Mission type.
        mission_type: u8,
    },
    /// `MISSION_ITEM_INT` or `MISSION_ITEM`: item `seq` of an upload.
    Item {
        /// Item number.
        seq: u16,
        /// The item.
        item: MissionItem,
        /// Mission type.
        mission_type: u8,
    },
    /// `MISSION_CLEAR_ALL`.
    ClearAll {
        /// Mission type.
        mission_type: u8,
    },
    /// `MISSION_SET_CURRENT`: the item a mission start begins with.
    SetCurrent {
        /// Item number.
        seq: u16,
    },
    /// `MISSION_ACK` from the ground station (the end of a download, or its cancel).
    Ack {
        /// Mission type.
        mission_type: u8,
    },
    /// `SET_GPS_GLOBAL_ORIGIN`: the local frame's origin on WGS84 (for global mission items).
    SetOrigin {
        /// Latitude \[deg × 10⁷\].
        latitude_e7: i32,
        /// Longitude \[deg × 10⁷\].
        longitude_e7: i32,
        /// Altitude above mean sea level \[mm\].
        altitude_mm: i32,
    },
}
