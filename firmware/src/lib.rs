//! Board-independent parts of the STM32F405 firmware: the clock plan and the boot report
//! (the set-up, its a-priori bound certificate and the controller built from it).
//!
//! Nothing here touches a register or logs: it computes plain values that the binary
//! (`src/main.rs`) applies to the hardware and formats with defmt. It is `no_std` and builds for
//! both the MCU and the host, where its unit tests run (`cargo test -p firmware`).
#![cfg_attr(not(test), no_std)]
#![deny(missing_docs)]

pub mod clocks;
pub mod report;
