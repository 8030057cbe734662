#!/usr/bin/env bash
# The project's test command (README, "Run all the tests"; .ci/run calls exactly this).
# Installs what it needs (the thumbv7em target, clippy, rustfmt), then: formatting, every host
# test (unit, property, cross-crate, end to end), clippy with warnings denied, and the no_std
# controller-core and the firmware built for the Cortex-M4F (thumbv7em-none-eabihf).
# Idempotent: re-running it changes nothing that is already installed.
set -euo pipefail
cd "$(dirname "$0")/.."

step() { printf '\n==> %s\n' "$*"; }

step "toolchain: thumbv7em-none-eabihf target, clippy, rustfmt"
rustup target add thumbv7em-none-eabihf
rustup component add clippy rustfmt

step "formatting (cargo fmt --check)"
cargo fmt --all -- --check

step "host tests (cargo test --workspace)"
cargo test --workspace

step "clippy, warnings denied (host, all targets)"
cargo clippy --workspace --all-targets -- -D warnings

step "controller-core for thumbv7em-none-eabihf (no_std, no alloc)"
cargo build -p controller-core --target thumbv7em-none-eabihf --release

step "firmware for thumbv7em-none-eabihf"
cargo clippy -p firmware --target thumbv7em-none-eabihf --release -- -D warnings
cargo build -p firmware --target thumbv7em-none-eabihf --release

step "firmware size budget (flash <= 128 KiB, static RAM <= 32 KiB)"
bash firmware/check-size.sh

printf '\n==> all checks passed\n'
