#!/usr/bin/env bash
# The Cortex-M4F step bench: instruction counts of the firmware's control step on QEMU's
# mps2-an386 (Cortex-M4 with FPU), and the agreement of its f32 outputs with the host.
#
#   bash firmware/qemu/bench.sh [--budget N] [other m4f-bench options]
#
# 1. builds the TCG plugin (firmware/qemu/build-plugin.sh: gcc);
# 2. builds the step-bench ELF (`cargo fw-qemu`: thumbv7em-none-eabihf, release, board-mps2-an386;
#    with the bench-fixtures feature);
# 3. runs `m4f-bench` (host-sim, test profile, or $M4F_BENCH): QEMU + plugin, counts per step, ARM-vs-host comparison,
#    table; exit 1 on a disagreement or when the largest full step exceeds the budget.
#
# Budget: a flight tick's full step (10 IMU samples, one ATT_POS_MOCAP frame, control_tick)
# must stay within BUDGET instructions. Measured when it was set: maximum 7 045, median 6 969
# instructions (QEMU 7.2, rustc 1.95; docs/m4f-bench.md); the budget is that maximum plus 15 %
# (8 101.75), rounded up to 8 200. `--budget N` overrides it. Needs qemu-system-arm (>= 7.2, with TCG plugin
# support, as Debian ships it), gcc and the thumbv7em-none-eabihf Rust target.
set -euo pipefail

BUDGET=8200
args=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --budget)
      BUDGET="${2:?--budget needs a number}"
      shift 2
      ;;
    --budget=*)
      BUDGET="${1#--budget=}"
      shift
      ;;
    *)
      args+=("$1")
      shift
      ;;
  esac
done

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
cd "$root"
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$root/target}"

for tool in qemu-system-arm gcc; do
  if ! command -v "$tool" >/dev/null; then
    echo "bench.sh: $tool not found (apt-get install qemu-system-arm gcc)" >&2
    exit 2
  fi
done
if command -v rustup >/dev/null && ! rustup target list --installed | grep -qx thumbv7em-none-eabihf; then
  rustup target add thumbv7em-none-eabihf
fi

plugin="$(bash "$here/build-plugin.sh")"
cargo fw-qemu --bin step-bench --features bench-fixtures
elf="$CARGO_TARGET_DIR/thumbv7em-none-eabihf/release/step-bench"
# m4f-bench is $M4F_BENCH if set (the test command passes the one its host tests built), else the
# test profile's build (the dev profile's opt-level 2): the host side only replays the fixtures to
# compare outputs (floats do not depend on the optimisation level); a release build (fat LTO)
# would add minutes.
if [ -n "${M4F_BENCH:-}" ]; then
  bench="$M4F_BENCH"
else
  cargo build --workspace --profile test --bin m4f-bench
  bench="$CARGO_TARGET_DIR/debug/m4f-bench"
fi
"$bench" \
  --elf "$elf" --plugin "$plugin" --budget "$BUDGET" ${args[@]+"${args[@]}"}
