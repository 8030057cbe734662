#!/usr/bin/env bash
# A real MAVLink client (pymavlink, pinned) against the firmware on QEMU, in lockstep:
#   bash tests/mavlink-client/run.sh <firmware-mps2-an386 ELF> <trusted-link ELF>
# the default build (its UART untrusted, as a radio) and the same built with
# FIRMWARE_MAVLINK_LINK_TRUST=trusted (a wired console; tests/run-all.sh builds both).
# Creates (once) a virtual environment under the target directory with requirements.txt
# (venv.sh), then runs gcs_client.py, which asserts what docs/mavlink.md promises (README,
# "MAVLink").
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
elf="${1:?usage: run.sh <firmware-mps2-an386 ELF> <trusted-link ELF>}"
elf_trusted="${2:?usage: run.sh <firmware-mps2-an386 ELF> <trusted-link ELF>}"
python="$(bash "$here/venv.sh")"
exec "$python" "$here/gcs_client.py" "$elf" "$elf_trusted"
