#!/usr/bin/env bash
# The pymavlink virtual environment of the MAVLink client tests (run.sh, qgc_connect.sh):
#   python="$(bash tests/mavlink-client/venv.sh)"
# Creates it (once, again when requirements.txt changes) under the target directory with the
# pinned requirements.txt, installing python3-venv with apt if missing; prints its python.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
base="${CARGO_TARGET_DIR:-$root/target}"
case "$base" in /*) ;; *) base="$root/$base" ;; esac
venv="$base/pymavlink-venv"
stamp="$venv/.requirements"
if [ ! -x "$venv/bin/python" ] || ! cmp -s "$here/requirements.txt" "$stamp"; then
  if ! python3 -c 'import venv, ensurepip' 2>/dev/null; then
    sudo_if_needed() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }
    sudo_if_needed apt-get update -qq >&2
    sudo_if_needed env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq python3-venv >&2
  fi
  rm -rf "$venv"
  python3 -m venv "$venv" >&2
  "$venv/bin/pip" install -q --disable-pip-version-check -r "$here/requirements.txt" >&2
  cp "$here/requirements.txt" "$stamp"
fi
echo "$venv/bin/python"
