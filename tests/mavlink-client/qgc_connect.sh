#!/usr/bin/env bash
# QGroundControl's connect sequence (qgc_connect.py, pymavlink) against host-sim with a ground
# station on UDP:
#   bash tests/mavlink-client/qgc_connect.sh sil|pil [firmware-mps2-an386 ELF, for pil]
# Starts `host-sim sil|pil --gcs-udp 127.0.0.1:PORT` (PORT a free one) in the background, runs
# the script listening on PORT, then stops host-sim (and, for pil, its QEMU). The exit status is
# the script's. host-sim is $HOST_SIM if set, else the test-profile build (cargo builds it if needed);
# the ELF defaults to the target directory's mps2-an386 release build (cargo fw-qemu).
#
# The run must outlast the script: sil --gcs-udp is paced to the wall clock (1 s simulated per
# second) and pil runs at most at real time, in practice about a third of it on QEMU, so both
# get a long --duration (600 s simulated) and are stopped as soon as the script is done.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
mode="${1:-}"
case "$mode" in sil | pil) ;; *)
  echo "usage: qgc_connect.sh sil|pil [firmware-mps2-an386 ELF]" >&2
  exit 2
  ;;
esac
target="${CARGO_TARGET_DIR:-$root/target}"
case "$target" in /*) ;; *) target="$root/$target" ;; esac
python="$(bash "$here/venv.sh")"
if [ -n "${HOST_SIM:-}" ]; then
  host_sim="$HOST_SIM"
else
  # The test profile with the workspace's features, as the test command builds it.
  (cd "$root" && cargo build -q --workspace --profile test --bin host-sim)
  host_sim="$target/debug/host-sim"
fi
out="$(mktemp -d)"
port="$("$python" -c 'import socket; s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')"
args=("$mode" --gcs-udp "127.0.0.1:$port" --duration 600 --out "$out/run")
if [ "$mode" = pil ]; then
  args+=(--elf "${2:-$target/thumbv7em-none-eabihf/release/firmware-mps2-an386}")
fi
# Its own process group (setsid), so that stopping it also stops the QEMU it started, as
# Ctrl-C in a terminal would.
setsid "$host_sim" "${args[@]}" >"$out/host-sim.log" 2>&1 &
pid=$!
stop() {
  if kill -0 "$pid" 2>/dev/null; then
    kill -INT -- "-$pid" 2>/dev/null || true
    sleep 1
    kill -KILL -- "-$pid" 2>/dev/null || true
  fi
  wait "$pid" 2>/dev/null || true
}
trap stop EXIT
echo "host-sim $mode --gcs-udp 127.0.0.1:$port (pid $pid, log $out/host-sim.log)"
# PIL: QEMU boots and the first heartbeat comes about 3 s later; the per-step timeouts of the
# script are sized for that.
status=0
"$python" "$here/qgc_connect.py" --port "$port" --lose-every 7 || status=$?
if [ "$status" -ne 0 ] || ! kill -0 "$pid" 2>/dev/null; then
  echo "--- host-sim log (tail) ---"
  tail -n 20 "$out/host-sim.log"
fi
stop
trap - EXIT
rm -rf "$out"
exit "$status"
