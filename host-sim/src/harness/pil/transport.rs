//! The byte link between the processor-in-the-loop host and the flight software under test:
//! QEMU's serial port ([`Qemu`] in [`Io::SerialLink`](crate::harness::qemu::Io::SerialLink)
//! mode), or an in-process fake in tests.

use std::time::Duration;

use anyhow::Result;

use crate::harness::qemu::{Qemu, Received};

/// A byte link to the flight software under test: the emulator's serial port, or an
/// in-process fake in tests.
pub trait Transport {
    /// Sends bytes to the firmware's serial port. Blocking is backpressure. Errors: the link
    /// is gone (the emulator exited).
    fn send(&mut self, bytes: &[u8]) -> Result<()>;
    /// Waits at most `timeout` for bytes from the firmware.
    fn receive(&mut self, timeout: Duration) -> Received;
    /// Why the link closed, for an error message: exit status, log tail (empty if unknown).
    fn post_mortem(&mut self) -> String;
}

impl Transport for Qemu {
    fn send(&mut self, bytes: &[u8]) -> Result<()> {
        Qemu::send(self, bytes)
    }

    fn receive(&mut self, timeout: Duration) -> Received {
        Qemu::receive(self, timeout)
    }

    fn post_mortem(&mut self) -> String {
        Qemu::post_mortem(self)
    }
}
