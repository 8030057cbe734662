#!/usr/bin/env bash
# A real MAVLink client (pymavlink, pinned) against the firmware on QEMU, in lockstep:
#   bash tests/mavlink-client/run.sh <firmware-mps2-an386 ELF> <trusted-link ELF>
# the default build (its UART untrusted, as a radio) and the same built with
# FIRMWARE_MAVLINK_LINK_TRUST=trusted (a wired console; tests/run-all.sh builds both).
# Creates (once) a virtual environment under the target directory with requirements.txt, then
# runs gcs_client.py, which asserts what docs/mavlink.md promises (README, "MAVLink").
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
elf="${1:?usage: run.sh <firmware-mps2-an386 ELF> <trusted-link ELF>}"
elf_trusted="${2:?usage: run.sh <firmware-mps2-an386 ELF> <trusted-link ELF>}"
base="${CARGO_TARGET_DIR:-$root/target}"
case "$base" in /*) ;; *) base="$root/$base" ;; esac
venv="$base/pymavlink-venv"
stamp="$venv/.requirements"
if [ ! -x "$venv/bin/python" ] || ! cmp -s "$here/requirements.txt" "$stamp"; then
  if ! python3 -c 'import venv, ensurepip' 2>/dev/null; then
    sudo_if_needed() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }
    sudo_if_needed apt-get update -qq
    sudo_if_needed env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq python3-venv
  fi
  rm -rf "$venv"
  python3 -m venv "$venv"
  "$venv/bin/pip" install -q --disable-pip-version-check -r "$here/requirements.txt"
  cp "$here/requirements.txt" "$stamp"
fi
exec "$venv/bin/python" "$here/gcs_client.py" "$elf" "$elf_trusted"
