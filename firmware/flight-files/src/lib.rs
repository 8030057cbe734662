//! The files the firmware and host-sim share, and the code that reads them.
//!
//! - [`control_rate`]: the allowed control-law rates (`no_std`; the flight build uses it);
//! - with the `files` feature (std, serde, toml; host-sim, the tests and the firmware's build
//!   script): `vehicle_file` reads and checks vehicle files (`host-sim/vehicles/*.toml`,
//!   docs/vehicles.md), `flight_tables` holds the `[limits]`, `[gains]` and `[trajectory]`
//!   tables of scenario and flight files, `flight_file` turns the build's flight file into
//!   the firmware's `OUT_DIR/flight.rs`, `bench_fixtures` writes the bench fixtures'
//!   constants, and `shared` holds the two files both sides read.
//!
//! The firmware re-exports these modules under their old paths (`firmware::control_rate`,
//! `firmware::vehicle_file`, `firmware::flight_tables`).
#![cfg_attr(not(feature = "files"), no_std)]
#![deny(missing_docs)]

#[cfg(feature = "files")]
pub mod bench_fixtures;
pub mod control_rate;
#[cfg(feature = "files")]
pub mod flight_file;
#[cfg(feature = "files")]
pub mod flight_tables;
#[cfg(feature = "files")]
pub mod shared;
#[cfg(feature = "files")]
pub mod vehicle_file;
