#!/usr/bin/env bash
# Builds the instruction-counting QEMU TCG plugin (firmware/qemu/insn_count.c) into
# ${CARGO_TARGET_DIR:-target}/qemu/libinsn_count.so and prints its path.
# Needs gcc; no QEMU headers (the plugin declares QEMU 7.2's plugin API v1 itself).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
target="${CARGO_TARGET_DIR:-$root/target}"
out="$target/qemu/libinsn_count.so"
mkdir -p "$target/qemu"
if [[ ! -f "$out" || "$here/insn_count.c" -nt "$out" ]]; then
  gcc -O2 -std=gnu11 -Wall -Wextra -Werror -shared -fPIC -fvisibility=hidden \
    -o "$out" "$here/insn_count.c"
fi
echo "$out"
