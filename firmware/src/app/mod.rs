//! The board-independent task layer of the MCU firmware: what every board runs around the
//! [`crate::pipeline::FlightPipeline`], with the hardware left to the board layers
//! (`src/bin/stm32f405/` for the STM32F405, `src/bin/mps2_an386/` for QEMU's Cortex-M4F).
//!
//! - [`control`]: the control loop (drain inputs → `control_tick` → motors → telemetry →
//!   timing → watchdog), generic over a [`control::ControlClock`] (a hardware deadline timer, or
//!   the simulation's clock in processor-in-the-loop), a [`control::MotorSink`] and a
//!   [`control::Watchdog`];
//! - [`queues`]: the fixed-size queues between the control task and the I/O tasks;
//! - [`logger`]: the defmt log task (events, 1 Hz timing and counters, 10 Hz flight summary);
//! - [`boot_log`]: the boot banner (set-up, certificate, mixer fit);
//! - [`param_flash`]: restoring the parameters from a board's flash at boot and saving them
//!   after each accepted `PARAM_SET` ([`crate::flash_store`]).
//!
//! Built for the MCU only (`target_os = "none"`): it needs embassy and defmt. Its logic (the
//! pipeline, the timing statistics, the reports) lives in the host-tested modules it calls.

pub mod boot_log;
pub mod control;
pub mod logger;
pub mod param_flash;
pub mod queues;
