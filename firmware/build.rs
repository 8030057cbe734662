//! Puts the workspace's `memory.x` where cortex-m-rt's `link.x` finds it.
//!
//! `link.x` does `INCLUDE memory.x`, which the linker resolves against its search path (and the
//! current directory, which differs between cargo invocations). Copying the file into `OUT_DIR`
//! and adding `OUT_DIR` to the search path makes the bare-metal link independent of where cargo
//! is run from. Host builds (the stub binary, the tests) do not link against `link.x`, so this
//! script does nothing for them.

use std::env;
use std::fs;
use std::path::PathBuf;

fn main() {
    let manifest_dir = PathBuf::from(
        env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR for build scripts"),
    );
    let memory_x = manifest_dir.join("..").join("memory.x");
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
            "cannot read the linker memory map {} (expected at the workspace root): {e}",
            memory_x.display()
        )
    });
    let dest = out_dir.join("memory.x");
    fs::write(&dest, contents).unwrap_or_else(|e| panic!("cannot write {}: {e}", dest.display()));
    println!("cargo:rustc-link-search={}", out_dir.display());
}
