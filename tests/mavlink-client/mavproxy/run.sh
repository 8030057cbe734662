#!/usr/bin/env bash
# A scripted MAVProxy session (pinned, own virtual environment) against the firmware in the
# loop over UDP: bash tests/mavlink-client/mavproxy/run.sh <host-sim binary>
# Creates (once) a virtual environment under the target directory with requirements.txt, then
# runs session.py (fetch the parameters, upload a mission with the wp module, download it, arm).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../../.." && pwd)"
host_sim="${1:?usage: run.sh <host-sim binary>}"
base="${CARGO_TARGET_DIR:-$root/target}"
case "$base" in /*) ;; *) base="$root/$base" ;; esac
venv="$base/mavproxy-venv"
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
exec "$venv/bin/python" "$here/session.py" "$host_sim"
