#!/usr/bin/env bash
# The project's test command (README, "The two commands"; .ci/run calls exactly this).
# Installs what it needs (the thumbv7em target, clippy, rustfmt, QEMU, cargo-modules, a Python virtual
# environment with pymavlink, another with MAVProxy), then: formatting, every
# host test (unit, property, cross-crate, end to end), the import-cycle check, clippy and rustdoc with warnings denied, the no_std
# controller-core and the firmware built for the Cortex-M4F (thumbv7em-none-eabihf) for both
# boards, the processor-in-the-loop flight on QEMU and the M4F instruction budget.
# Idempotent: re-running it changes nothing that is already installed.
set -euo pipefail
cd "$(dirname "$0")/.."

# Each step says when it starts (minutes:seconds since this script started), so a slow run shows
# where its time went.
step() { printf '\n==> [%d:%02d] %s\n' $((SECONDS / 60)) $((SECONDS % 60)) "$*"; }

sudo_if_needed() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }

step "the null device: /dev/null must be the character device (1, 3)"
# Seen on a CI machine: /dev/null a regular file. Every `2>/dev/null` then wrote into it, and every
# program given "no input" read that text instead: cargo's rustc probe (clippy-driver) parsed it as
# Rust source and the run stopped. Put the device back before anything else reads or writes it.
if [ ! -c /dev/null ]; then
  echo "/dev/null is not a character device ($(stat -c %F /dev/null)); recreating it"
  sudo_if_needed rm -f /dev/null
  sudo_if_needed mknod -m 666 /dev/null c 1 3
fi
[ -c /dev/null ] || {
  echo "/dev/null is still not the null device: fix the machine (mknod -m 666 /dev/null c 1 3)" >&2
  exit 1
}

step "toolchain: thumbv7em-none-eabihf target, clippy, rustfmt"
rustup target add thumbv7em-none-eabihf
rustup component add clippy rustfmt

step "QEMU (qemu-system-arm, Debian package) for the mps2-an386 board"
if ! command -v qemu-system-arm >/dev/null 2>&1; then
  sudo_if_needed apt-get update -qq
  sudo_if_needed env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq qemu-system-arm
fi
qemu-system-arm --version | head -1

step "formatting (cargo fmt --check)"
cargo fmt --all -- --check

step "host tests (cargo test --workspace)"
cargo test --workspace

step "firmware with the HIL messages (host tests and clippy, --features hil)"
cargo test -p firmware --lib --features hil
cargo clippy -p firmware --all-targets --features hil -- -D warnings

step "firmware built with the paper's flight file (--features uncertified-paper only; it arms loudly)"
paper_flight=(env FIRMWARE_FLIGHT_FILE=firmware/flights/paper.toml)
"${paper_flight[@]}" cargo test -p firmware --lib --features uncertified-paper
"${paper_flight[@]}" cargo clippy -p firmware --target thumbv7em-none-eabihf --release \
  --features uncertified-paper -- -D warnings
# Without the feature the build refuses that file.
if "${paper_flight[@]}" cargo check -p firmware --lib 2>/dev/null; then
  echo "the paper's flight file built without --features uncertified-paper" >&2
  exit 1
fi

step "firmware built with each preset design's flight file (airmode, the vertical channel, the local regime where chosen): the gate certifies it and it arms"
for preset in crazyflie-2.1 hummingbird x500; do
  FIRMWARE_FLIGHT_FILE="host-sim/designs/$preset/firmware.toml" \
    cargo test -p firmware --lib built_config_is_certified_and_arms
done

step "firmware built with the test fixtures' flight files (airmode and a local regime; a local regime with the compensated heading; a local regime with its own vertical levels): the gate certifies each and it arms"
for fixture in crazyflie-airmode-local x500-compensated-local x500-local-vertical-levels; do
  FIRMWARE_FLIGHT_FILE="firmware/flights/fixtures/$fixture.toml" \
    cargo test -p firmware --lib built_config_is_certified_and_arms
done

step "no import cycle between the modules of any crate (cargo-modules 0.27.0, installed if missing)"
# cargo-modules resolves every crate's `use` edges (rust-analyzer); tests/module_cycles.py fails on
# a cycle between modules at any depth. (`--acyclic` itself checks items: a type and its own
# methods would count as a cycle.) The first install builds rust-analyzer's crates: minutes.
if [ "$(cargo modules --version 2>/dev/null)" != "cargo-modules 0.27.0" ]; then
  rustup component add rust-src
  cargo install cargo-modules --version 0.27.0 --locked
fi
module_graph=(--no-externs --no-sysroot --no-fns --no-traits --no-types --no-owns --layout dot)
for target in "controller-core --lib" "flight-files --lib" "firmware --lib" "host-sim --lib" \
  "host-sim --bin host-sim" "tests --lib"; do
  read -r -a which <<<"$target"
  cargo modules dependencies --package "${which[@]}" "${module_graph[@]}" |
    python3 tests/module_cycles.py "$target"
done

step "clippy, warnings denied (host, all targets)"
cargo clippy --workspace --all-targets -- -D warnings

step "API documentation, warnings denied (cargo doc --workspace --no-deps): links resolve"
RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps -q

step "coverage-guided fuzzing (libFuzzer on stable; tests/fuzz/run.sh, docs/fuzzing.md)"
bash tests/fuzz/run.sh

step "controller-core for thumbv7em-none-eabihf (no_std, no alloc)"
cargo build -p controller-core --target thumbv7em-none-eabihf --release

step "firmware for thumbv7em-none-eabihf"
cargo clippy -p firmware --target thumbv7em-none-eabihf --release -- -D warnings
cargo fw-build

step "firmware size budget (flash <= 384 KiB, static RAM <= 64 KiB)"
bash firmware/check-size.sh

step "firmware for QEMU mps2-an386 (the same tasks, the processor-in-the-loop board)"
mps2=(-p firmware --bin firmware-mps2-an386 --target thumbv7em-none-eabihf --release
  --no-default-features --features board-mps2-an386)
cargo clippy "${mps2[@]}" -- -D warnings
cargo fw-qemu
# Absolute: the PIL test runs with the tests package as its working directory.
target_dir="${CARGO_TARGET_DIR:-target}"
case "$target_dir" in /*) ;; *) target_dir="$PWD/$target_dir" ;; esac
elf_mps2="$target_dir/thumbv7em-none-eabihf/release/firmware-mps2-an386"
bash firmware/qemu/boot-check.sh "$elf_mps2"

step "processor in the loop: the default build's x500 from upside down, firmware on QEMU (lockstep), law at 100 Hz (the whole flight) and 1 kHz (the recovery, 0 overruns); lockstep determinism (two short runs, whole vs random writes, same telemetry)"
# The law runs at 100, 250, 500 or 1000 Hz; any other rate stops the build.
if FIRMWARE_CONTROL_RATE_HZ=300 cargo check -p firmware --lib 2>/dev/null; then
  echo "the firmware built with the law at 300 Hz" >&2
  exit 1
fi
# The same flight file with the law at 1 kHz, set aside; the same with its UART marked as a
# trusted wired console (the pymavlink client sets up signing over it; the default build refuses
# that), set aside; then the default (100 Hz, untrusted) build again.
FIRMWARE_CONTROL_RATE_HZ=1000 cargo fw-qemu
mkdir -p "$target_dir/pil-1khz" && cp "$elf_mps2" "$target_dir/pil-1khz/"
FIRMWARE_MAVLINK_LINK_TRUST=trusted cargo fw-qemu
mkdir -p "$target_dir/pil-trusted" && cp "$elf_mps2" "$target_dir/pil-trusted/"
cargo fw-qemu
# Two at a time: the emulated clock is tied to the instructions run (QEMU -icount), so a flight's
# telemetry, its overrun count and its checks do not depend on what else the host runs; the
# determinism test loads every core on purpose.
# `--workspace`: the same feature set as the host tests, so their build is reused (`-p tests`
# alone resolves other features and rebuilds the dependencies: about 2 minutes).
PIL_FIRMWARE_ELF="$elf_mps2" PIL_FIRMWARE_ELF_1KHZ="$target_dir/pil-1khz/firmware-mps2-an386" \
  cargo test --workspace --test pil_qemu -- --ignored --nocapture --test-threads 2

step "a real MAVLink client: pymavlink (pinned, own virtual environment) as ground station and mocap bridge against the firmware on QEMU; a stranger's SETUP_SIGNING refused on the default (untrusted) link, signing set up over a trusted one; missions uploaded (refused naming the condition, accepted), downloaded, cleared, flown to each item reached"
bash tests/mavlink-client/run.sh "$elf_mps2" "$target_dir/pil-trusted/firmware-mps2-an386"

step "QGroundControl's connect sequence (pymavlink, qgc_connect.py: heartbeat, parameters, mission/fence/rally lists) against sil --gcs-udp and pil --gcs-udp"
# host-sim and m4f-bench as the host tests built them (`cargo test` builds a package's binaries for
# its integration tests, into target/debug). `--no-run` only checks they are current: a
# `cargo build` would resolve the features without the dev-dependencies' and build every
# dependency again (about 2 1/2 minutes on 2 cores in a fresh clone).
cargo test --workspace --no-run -q
host_sim_debug="$target_dir/debug/host-sim"
for mode in sil pil; do
  HOST_SIM="$host_sim_debug" bash tests/mavlink-client/qgc_connect.sh "$mode" "$elf_mps2"
done

step "MAVProxy (pinned, own virtual environment), scripted against the firmware in the loop (host-sim sil --gcs-udp): parameters fetched, a mission uploaded with its wp module, certified and accepted, downloaded, armed"
# The same host-sim (opt-level 2): the session is paced to the wall clock.
bash tests/mavlink-client/mavproxy/run.sh "$host_sim_debug"

step "Cortex-M4F instruction counts of the control step, f32 on ARM vs host, budget"
M4F_BENCH="$target_dir/debug/m4f-bench" bash firmware/qemu/bench.sh

step "all checks passed"
