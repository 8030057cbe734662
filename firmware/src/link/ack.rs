//! `COMMAND_ACK` with its extension fields `target_system` and `target_component`, so that the
//! answer goes back to the sender (MAVLink command protocol,
//! <https://mavlink.io/en/services/command.html>). The `mavlink` crate's generated
//! `COMMAND_ACK_DATA` has them only with its `mav2-message-extensions` feature, which in 0.21
//! makes its code generator a normal (std) dependency: no build for the MCU. The payload is
//! simple enough to lay out here: command (u16), result (u8), progress (u8), result_param2
//! (i32), target_system (u8), target_component (u8), little endian.

use mavlink::dialects::common::{MavCmd, MavMessage, MavResult, COMMAND_ACK_DATA};
use mavlink::error::ParserError;
use mavlink::{MavlinkVersion, MessageData};

/// A `COMMAND_ACK` addressed to the command's sender.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CommandAck {
    /// The command acknowledged.
    pub command: MavCmd,
    /// Its result.
    pub result: MavResult,
    /// Sender's system id.
    pub target_system: u8,
    /// Sender's component id.
    pub target_component: u8,
}

impl MessageData for CommandAck {
    type Message = MavMessage;
    const ID: u32 = COMMAND_ACK_DATA::ID;
    const NAME: &'static str = COMMAND_ACK_DATA::NAME;
    const EXTRA_CRC: u8 = COMMAND_ACK_DATA::EXTRA_CRC;
    const ENCODED_LEN: usize = 10;

    /// Writes the payload into `payload` (at least 10 bytes, or it panics, as the trait says);
    /// MAVLink 2 drops trailing zero bytes (at least one byte stays).
    fn ser(&self, version: MavlinkVersion, payload: &mut [u8]) -> usize {
        let base = COMMAND_ACK_DATA {
            command: self.command,
            result: self.result,
        };
        let n = base.ser(MavlinkVersion::V1, payload);
        payload[n..Self::ENCODED_LEN].fill(0);
        payload[8] = self.target_system;
        payload[9] = self.target_component;
        match version {
            MavlinkVersion::V1 => n,
            MavlinkVersion::V2 => {
                let used = payload[..Self::ENCODED_LEN]
                    .iter()
                    .rposition(|&b| b != 0)
                    .map_or(1, |i| i + 1);
                used
            }
        }
    }

    /// Reads a payload, short ones zero-extended (MAVLink 2). Errors: the command or result
    /// is not in the dialect.
    fn deser(version: MavlinkVersion, payload: &[u8]) -> Result<Self, ParserError> {
        let mut full = [0u8; Self::ENCODED_LEN];
        let n = payload.len().min(Self::ENCODED_LEN);
        full[..n].copy_from_slice(&payload[..n]);
        let base = COMMAND_ACK_DATA::deser(version, &full[..3])?;
        Ok(Self {
            command: base.command,
            result: base.result,
            target_system: full[8],
            target_component: full[9],
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The layout matches the mavlink crate's for the base fields, and the extension bytes
    /// sit at offsets 8 and 9 (the common.xml order); trailing zeros are truncated in
    /// MAVLink 2, so an ACK to (0, 0) is the 3-byte base payload.
    #[test]
    fn layout_and_round_trip() {
        let ack = CommandAck {
            command: MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
            result: MavResult::MAV_RESULT_TEMPORARILY_REJECTED,
            target_system: 255,
            target_component: 190,
        };
        let mut p = [0xAAu8; 255];
        let n = ack.ser(MavlinkVersion::V2, &mut p);
        assert_eq!(n, 10);
        assert_eq!(&p[..10], &[144, 1, 1, 0, 0, 0, 0, 0, 255, 190]);
        assert_eq!(
            CommandAck::deser(MavlinkVersion::V2, &p[..n]).ok(),
            Some(ack)
        );
        let base = COMMAND_ACK_DATA::deser(MavlinkVersion::V2, &p[..n]).unwrap();
        assert_eq!((base.command, base.result), (ack.command, ack.result));
        let to_nobody = CommandAck {
            target_system: 0,
            target_component: 0,
            ..ack
        };
        assert_eq!(to_nobody.ser(MavlinkVersion::V2, &mut p), 3);
    }
}
