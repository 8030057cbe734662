//! The mission microservice's messages (`MISSION_*`, and `SET_GPS_GLOBAL_ORIGIN` for global
//! items) to [`Inbound::Mission`]: addressing, the
//! MAVLink 2 extension field `mission_type` (read from the payload: the `mavlink` crate's
//! structs do not carry it), and `MISSION_ITEM`'s float position scaled to the integer
//! message's units ([`MissionItem::from_float`]).

// MISSION_ITEM, MISSION_REQUEST and MISSION_SET_CURRENT are deprecated in MAVLink's common
// set but still sent by ground stations (MAVProxy's wp module, older QGroundControl).
#![allow(deprecated)]

use mavlink::dialects::common::{
    MISSION_ACK_DATA, MISSION_CLEAR_ALL_DATA, MISSION_COUNT_DATA, MISSION_ITEM_DATA,
    MISSION_ITEM_INT_DATA, MISSION_REQUEST_DATA, MISSION_REQUEST_INT_DATA,
    MISSION_REQUEST_LIST_DATA, MISSION_SET_CURRENT_DATA, SET_GPS_GLOBAL_ORIGIN_DATA,
};
use mavlink::{MavlinkVersion, MessageData};

use super::interpret::{Address, Interpretation};
use super::{Inbound, Sender};
use super::{MissionItem, MissionMessage};

/// Ids of the messages that change the stored mission or what is flown: with signing active
/// they must be signed.
pub(super) fn changes_mission(msgid: u32) -> bool {
    matches!(
        msgid,
        MISSION_COUNT_DATA::ID
            | MISSION_ITEM_DATA::ID
            | MISSION_ITEM_INT_DATA::ID
            | MISSION_CLEAR_ALL_DATA::ID
            | MISSION_SET_CURRENT_DATA::ID
            | SET_GPS_GLOBAL_ORIGIN_DATA::ID
    )
}

/// `mission_type`, the first extension byte after `D`'s base payload (0 when truncated away).
fn mission_type<D: MessageData>(payload: &[u8]) -> u8 {
    payload.get(D::ENCODED_LEN).copied().unwrap_or(0)
}

/// Interprets a `MISSION_*` payload; `None` for any other message id.
pub(super) fn interpret(
    us: Address,
    sender: Sender,
    msgid: u32,
    payload: &[u8],
    out: &mut Option<Inbound>,
) -> Option<Interpretation> {
    let v = MavlinkVersion::V2;
    macro_rules! decode {
        ($t:ty) => {
            match <$t>::deser(v, payload) {
                Ok(m) if us.accepts(m.target_system, m.target_component) => m,
                Ok(_) => return Some(Interpretation::Ignored),
                Err(_) => return Some(Interpretation::Malformed),
            }
        };
    }
    let message = match msgid {
        MISSION_REQUEST_LIST_DATA::ID => {
            decode!(MISSION_REQUEST_LIST_DATA);
            MissionMessage::RequestList {
                mission_type: mission_type::<MISSION_REQUEST_LIST_DATA>(payload),
            }
        }
        MISSION_REQUEST_INT_DATA::ID => MissionMessage::Request {
            seq: decode!(MISSION_REQUEST_INT_DATA).seq,
            mission_type: mission_type::<MISSION_REQUEST_INT_DATA>(payload),
        },
        MISSION_REQUEST_DATA::ID => MissionMessage::Request {
            seq: decode!(MISSION_REQUEST_DATA).seq,
            mission_type: mission_type::<MISSION_REQUEST_DATA>(payload),
        },
        MISSION_COUNT_DATA::ID => MissionMessage::Count {
            count: decode!(MISSION_COUNT_DATA).count,
            mission_type: mission_type::<MISSION_COUNT_DATA>(payload),
        },
        MISSION_ITEM_INT_DATA::ID => {
            let (seq, item) = MissionItem::from_int(&decode!(MISSION_ITEM_INT_DATA));
            MissionMessage::Item {
                seq,
                item,
                mission_type: mission_type::<MISSION_ITEM_INT_DATA>(payload),
            }
        }
        MISSION_ITEM_DATA::ID => {
            let (seq, item) = MissionItem::from_float(&decode!(MISSION_ITEM_DATA));
            MissionMessage::Item {
                seq,
                item,
                mission_type: mission_type::<MISSION_ITEM_DATA>(payload),
            }
        }
        MISSION_CLEAR_ALL_DATA::ID => {
            decode!(MISSION_CLEAR_ALL_DATA);
            MissionMessage::ClearAll {
                mission_type: mission_type::<MISSION_CLEAR_ALL_DATA>(payload),
            }
        }
        MISSION_SET_CURRENT_DATA::ID => MissionMessage::SetCurrent {
            seq: decode!(MISSION_SET_CURRENT_DATA).seq,
        },
        SET_GPS_GLOBAL_ORIGIN_DATA::ID => match SET_GPS_GLOBAL_ORIGIN_DATA::deser(v, payload) {
            // No target component in this message: the system's is enough.
            Ok(m) if us.accepts(m.target_system, 0) => MissionMessage::SetOrigin {
                latitude_e7: m.latitude,
                longitude_e7: m.longitude,
                altitude_mm: m.altitude,
            },
            Ok(_) => return Some(Interpretation::Ignored),
            Err(_) => return Some(Interpretation::Malformed),
        },
        MISSION_ACK_DATA::ID => {
            decode!(MISSION_ACK_DATA);
            MissionMessage::Ack {
                mission_type: mission_type::<MISSION_ACK_DATA>(payload),
            }
        }
        _ => return None,
    };
    *out = Some(Inbound::Mission { message, sender });
    Some(Interpretation::Accepted)
}
