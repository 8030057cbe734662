//! Coverage-guided fuzzing (libFuzzer, through `libfuzzer-sys`) of every input path of the
//! flight software: the MAVLink 2 stream decoder ([`targets::link_decoder`]), the flight
//! pipeline fed interleavings of link bytes, IMU samples and control ticks
//! ([`targets::pipeline`], input format [`script`]), and the TOML parsers of the vehicle files
//! ([`targets::vehicle_toml`]) and of host-sim's scenario files ([`targets::scenario_toml`]).
//!
//! Each target is a plain function of the input bytes that panics when an invariant fails; the
//! `fuzz_targets/*.rs` binaries wrap them in `fuzz_target!`, and the seed generator
//! (`src/bin/seeds.rs`, [`capture`]) records the software-in-the-loop flights that seed the
//! corpus. `tests/fuzz/run.sh` builds and runs them (docs/fuzzing.md).
#![deny(missing_docs)]

// The unit tests are built instrumented too (run.sh): libFuzzer defines the coverage callbacks.
#[cfg(test)]
extern crate libfuzzer_sys;

pub mod capture;
pub mod script;
pub mod targets;
