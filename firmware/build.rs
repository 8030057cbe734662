//! Three build-time jobs of the firmware crate.
//!
//! **The flight file** (every build). The firmware flies one flight file chosen at build time:
//! env `FIRMWARE_FLIGHT_FILE` (default `firmware/flights/x500.toml`): a vehicle file (read by
//! `flight_files::vehicle_file`) plus `[limits]`, `[gains]`, `[trajectory]` (read by
//! `flight_files::flight_tables`) and `[design]`.
//! `flight_files::flight_file::write` writes it to `OUT_DIR/flight.rs`, which `src/built_flight.rs` includes
//! (`FlightConfig::built()`). The control law's rate is the file's `[design] control_rate_hz`
//! (100 Hz if absent), or env `FIRMWARE_CONTROL_RATE_HZ` when set (the same vehicle at another
//! rate, e.g. the 1 kHz processor-in-the-loop build). The paper's set-up (`[vehicle] real_propeller = false`) is refused
//! unless the `uncertified-paper` feature is on.
//!
//! **The board's memory map** (bare-metal builds only). cortex-m-rt's `link.x` does
//! `INCLUDE memory.x`; the linker looks for it in the current directory first, which for cargo
//! is the workspace root, whose `memory.x` only does `INCLUDE board-memory.x`. This script copies
//! the board's map (`boards/stm32f405/memory.x` by default, `boards/mps2-an386/memory.x` with the
//! `board-mps2-an386` feature) into `OUT_DIR` as `board-memory.x` and puts `OUT_DIR` on the
//! linker search path. (The board's map cannot simply be called `memory.x` on the search path:
//! the workspace root's file would shadow it.) Host builds do not link against `link.x`.
//!
//! **The bench fixtures' scenario values** (`bench-fixtures` feature only). `step_inputs` copies
//! the paper scenario's initial state (`[initial]`) and the software-in-the-loop sensor models
//! (`[imu]`, `[mocap]`) from the two files the firmware and host-sim share, owned by the
//! `flight-files` crate (`firmware/flight-files/shared/`; host-sim's `scenarios/paper.toml` and
//! `scenarios/sil/sensors.toml` link to them); `flight_files::bench_fixtures` writes the
//! constants to `OUT_DIR/scenario_constants.rs`, which `src/step_inputs/scenario.rs` includes.
//! Nothing here reads a file of host-sim.
//!
//! The code that reads and generates lives in the `flight-files` crate (a build-dependency),
//! shared with the firmware library and host-sim: no source is included by path.

use std::env;
use std::fs;
use std::path::{Path, PathBuf};

fn main() {
    let manifest_dir = PathBuf::from(
        env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR for build scripts"),
    );
    let out_dir =
        PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR for build scripts"));
    println!("cargo:rerun-if-changed=build.rs");
    memory_map(&manifest_dir, &out_dir);
    flight_files::flight_file::write(&manifest_dir, &out_dir);
    #[cfg(feature = "bench-fixtures")]
    flight_files::bench_fixtures::write_scenario_constants(&out_dir);
}

/// Copies the board's memory map to `OUT_DIR/board-memory.x` (bare-metal builds).
fn memory_map(manifest_dir: &Path, out_dir: &Path) {
    let board = if env::var_os("CARGO_FEATURE_BOARD_MPS2_AN386").is_some() {
        "mps2-an386"
    } else {
        "stm32f405"
    };
    let memory_x = manifest_dir.join("boards").join(board).join("memory.x");
    println!("cargo:rerun-if-changed={}", memory_x.display());
    println!(
        "cargo:rerun-if-changed={}",
        manifest_dir.join("..").join("memory.x").display()
    );
    // CARGO_CFG_TARGET_OS is the *target's* OS ("none" for thumbv7em-none-eabihf); the build
    // script itself always runs on the host.
    if env::var("CARGO_CFG_TARGET_OS").as_deref() != Ok("none") {
        return;
    }
    let dest = out_dir.join("board-memory.x");
    fs::copy(&memory_x, &dest).unwrap_or_else(|e| {
        panic!(
            "cannot copy the linker memory map {} to {}: {e}",
            memory_x.display(),
            dest.display()
        )
    });
    println!("cargo:rustc-link-search={}", out_dir.display());
}
