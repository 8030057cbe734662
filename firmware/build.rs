//! Puts the board's memory map where the workspace's `memory.x` (`INCLUDE board-memory.x`)
//! finds it: `boards/stm32f405/memory.x` by default, `boards/mps2-an386/memory.x` with the
//! `board-mps2-an386` feature.
//!
//! `link.x` does `INCLUDE memory.x`, which the linker looks for in the current directory first
//! (the workspace root, for cargo) and then on its search path. Copying both files into
//! `OUT_DIR` and adding `OUT_DIR` to the search path makes the bare-metal link independent of
//! where cargo is run from. Host builds (the stub binary, the tests) do not link against `link.x`, so this
//! script does nothing for them.

use std::env;
use std::fs;
use std::path::PathBuf;

fn main() {
    let manifest_dir = PathBuf::from(
        env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR for build scripts"),
    );
    // Cargo sets CARGO_FEATURE_<NAME> for every feature enabled on this package.
    let memory_x = if env::var_os("CARGO_FEATURE_BOARD_MPS2_AN386").is_some() {
        manifest_dir
            .join("boards")
            .join("mps2-an386")
            .join("memory.x")
    } else {
        manifest_dir
            .join("boards")
            .join("stm32f405")
            .join("memory.x")
    };
    let root_memory_x = manifest_dir.join("..").join("memory.x");
    println!("cargo:rerun-if-changed={}", root_memory_x.display());
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed={}", memory_x.display());

    // CARGO_CFG_TARGET_OS is the *target's* OS ("none" for thumbv7em-none-eabihf); the build
    // script itself always runs on the host.
    if env::var("CARGO_CFG_TARGET_OS").as_deref() != Ok("none") {
        return;
    }

    let out_dir =
        PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR for build scripts"));
    let contents = fs::read(&memory_x).unwrap_or_else(|e| {
        panic!(
            "cannot read the linker memory map {}: {e}",
            memory_x.display()
        )
    });
    let dest = out_dir.join("board-memory.x");
    fs::write(&dest, contents).unwrap_or_else(|e| panic!("cannot write {}: {e}", dest.display()));
    let dest = out_dir.join("memory.x");
    fs::copy(&root_memory_x, &dest).unwrap_or_else(|e| {
        panic!(
            "cannot copy {} to {}: {e}",
            root_memory_x.display(),
            dest.display()
        )
    });
    println!("cargo:rustc-link-search={}", out_dir.display());
}
