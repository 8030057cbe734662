//! Telemetry encoding: a message to a MAVLink 2 frame in a caller's buffer (unsigned; the
//! [`super::Decoder`] that holds the link's signing state signs it, [`super::Decoder::sign`]).

use mavlink::dialects::common::MavMessage;
use mavlink::{MAVLinkV2MessageRaw, MavHeader, MessageData};

/// Encodes `message` as a MAVLink 2 frame from (`system_id`, `component_id`) with `sequence`
/// into `out`. Returns the number of bytes written, 0 if `out` is too small (nothing written).
pub fn encode(
    message: &MavMessage,
    system_id: u8,
    component_id: u8,
    sequence: u8,
    out: &mut [u8],
) -> usize {
    let mut raw = MAVLinkV2MessageRaw::new();
    raw.serialize_message(header(system_id, component_id, sequence), message);
    copy_out(raw.raw_bytes(), out)
}

/// [`encode`] for one message type: links only that message's serializer (the firmware uses
/// this; `MavMessage::ser` matches over every message of the dialect, ~27 KiB of flash).
pub fn encode_data<D: MessageData>(
    message: &D,
    system_id: u8,
    component_id: u8,
    sequence: u8,
    out: &mut [u8],
) -> usize {
    let mut raw = MAVLinkV2MessageRaw::new();
    raw.serialize_message_data(header(system_id, component_id, sequence), message);
    copy_out(raw.raw_bytes(), out)
}

fn header(system_id: u8, component_id: u8, sequence: u8) -> MavHeader {
    MavHeader {
        system_id: u32::from(system_id),
        component_id,
        sequence,
    }
}

fn copy_out(bytes: &[u8], out: &mut [u8]) -> usize {
    if bytes.len() > out.len() {
        return 0;
    }
    out[..bytes.len()].copy_from_slice(bytes);
    bytes.len()
}
