//! Board-independent parts of the firmware: the boot report (the set-up, its a-priori bound
//! certificate and the controller built from it), the device drivers' pure parts ([`drivers`]),
//! and the flight logic: [`pipeline::FlightPipeline`] composes [`config`], [`frames`] (NED/FRD ↔
//! NWU/FLU), [`link`] (MAVLink 2: framing, checksum, signing), [`estimator`], [`imu_attitude`], [`flight_reference`],
//! [`mixer`] and [`safety`]; [`params`] is the table of parameters a ground station may tune
//! (MAVLink parameter protocol, each change certified), persisted on NOR flash by
//! [`flash_store`] and restored at boot only if still certified; host-sim flies the same pipeline in
//! software in the loop.
//!
//! On the MCU only, `app` is the board-independent task layer (control loop, queues, logger,
//! boot banner) that every board runs. Each board is one folder of binary sources, with its
//! clocks, pins and drivers' hardware side: the STM32F405 (`src/bin/stm32f405/`) and QEMU's
//! mps2-an386 (`src/bin/mps2_an386/`).
//!
//! [`airframe::Airframe`] is one vehicle (rigid body, rotors, motors, drag, name and source);
//! with the `vehicle-file` feature (host only: it brings std, serde and toml), `vehicle_file`
//! reads and checks the vehicle files that describe one (`host-sim/vehicles/*.toml`), and
//! `flight_tables` holds the `[limits]`, `[gains]` and `[trajectory]` tables of scenario and
//! flight files; `build.rs` compiles the same sources.
//!
//! With the `bench-fixtures` feature only (never in the flight build), `step_inputs` is the
//! deterministic control-step sequence of the Cortex-M4F bench (`src/bin/step_bench/`), the
//! criterion bench and host-sim's ARM-vs-host comparison.
//!
//! Apart from `app`, nothing here touches a register or logs: it computes plain values that
//! the binaries apply to the hardware and format with defmt. It is `no_std` and builds for
//! both the MCU and the host, where its unit tests run (`cargo test -p firmware`).
#![cfg_attr(not(test), no_std)]
#![deny(missing_docs)]

// Vehicle files are read on the host only (host-sim, tests); the flight build stays no_std.
#[cfg(feature = "vehicle-file")]
extern crate std;

pub mod airframe;
#[cfg(target_os = "none")]
pub mod app;
pub mod built_flight;

pub mod config;
pub use flight_files::control_rate;
pub mod drivers;
pub mod estimator;
pub mod flight_reference;
#[cfg(feature = "vehicle-file")]
pub use flight_files::flight_tables;
pub mod boot_report;
pub mod frames;
pub mod gate_failure;
#[cfg(feature = "ground-station")]
pub mod ground_station;
pub mod imu_attitude;
pub mod link;
pub mod mission;
pub mod mixer;
pub mod motor_order;
pub mod parameters;
pub mod pipeline;
pub mod safety;
#[cfg(feature = "bench-fixtures")]
pub mod step_inputs;
pub mod storage;
pub mod timing;

// The parameter modules under the paths they had before they were gathered in [`parameters`],
// and the boot report under its earlier name.
pub use boot_report as report;
#[cfg(feature = "vehicle-file")]
pub use flight_files::vehicle_file;
pub use parameters::store as param_store;
pub use parameters::table as params;
pub use storage::{erase_watchdog, flash_store};
