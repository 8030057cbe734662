#!/usr/bin/env bash
# Coverage-guided fuzzing with libFuzzer on the stable toolchain (docs/fuzzing.md).
#
#   bash tests/fuzz/run.sh                 # short: build, seeds, replay tests/fuzz/regressions,
#                                          # then FUZZ_SECONDS (default 12) s per target
#   bash tests/fuzz/run.sh long TARGET...  # FUZZ_RUNS (default 10^7) executions per target,
#                                          # one target at a time (at most FUZZ_MAX_SECONDS
#                                          # each if set), final statistics printed
#
# Targets: link_decoder, pipeline, vehicle_toml, scenario_toml. libfuzzer-sys builds libFuzzer
# from its bundled sources (a C++ compiler is needed, installed here if missing); the
# instrumentation is rustc's own SanitizerCoverage pass (`-Cpasses=sancov-module`, stable),
# which is what `cargo fuzz --sanitizer none` passes: no nightly, no extra cargo tool.
# Output: $CARGO_TARGET_DIR/fuzz/ (build, corpus/, artifacts/); a crash fails the run and
# leaves its input in artifacts/.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
mode="${1:-short}"
[ $# -gt 0 ] && shift
all_targets=(link_decoder pipeline vehicle_toml scenario_toml)

if ! command -v c++ >/dev/null 2>&1; then
  sudo_if_needed() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }
  sudo_if_needed apt-get update -qq
  sudo_if_needed env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq g++
fi

base="${CARGO_TARGET_DIR:-$root/target}"
case "$base" in /*) ;; *) base="$root/$base" ;; esac
work="$base/fuzz"
host="$(rustc -vV | sed -n 's/^host: //p')"
# The instrumentation cargo-fuzz uses (libFuzzer's inline 8-bit counters, PC table and
# comparison tracing); `--target` keeps it off build scripts and proc macros. `--cfg fuzzing`
# as cargo-fuzz; debug assertions and overflow checks are on in the fuzz crate's profile.
export RUSTFLAGS="-Cpasses=sancov-module -Cllvm-args=-sanitizer-coverage-level=4 \
-Cllvm-args=-sanitizer-coverage-inline-8bit-counters -Cllvm-args=-sanitizer-coverage-pc-table \
-Cllvm-args=-sanitizer-coverage-trace-compares --cfg fuzzing"
export CARGO_TARGET_DIR="$work/build"
(cd "$here" && cargo build --locked --release --target "$host" --bins)
if [ "$mode" = short ]; then
  # The crate's own checks: formatting (outside the main workspace's `cargo fmt --all`) and
  # its unit tests (script format, the replayed regressions).
  (cd "$here" && cargo fmt --check && cargo test --locked --release --target "$host" --lib)
fi
bin="$CARGO_TARGET_DIR/$host/release"

"$bin/seeds" "$work/seeds" "$root" >/dev/null
mkdir -p "$work/artifacts"

max_len() {
  case "$1" in
    pipeline) echo 12288 ;;
    link_decoder) echo 1100 ;;
    *) echo 4096 ;;
  esac
}

fuzz() { # target, libFuzzer options...
  local t="$1"
  shift
  mkdir -p "$work/corpus/$t"
  local dirs=("$work/corpus/$t" "$work/seeds/$t")
  # Past crashes seed their neighbourhood too.
  [ -d "$here/regressions/$t" ] && dirs+=("$here/regressions/$t")
  "$bin/$t" "${dirs[@]}" -max_len="$(max_len "$t")" \
    -artifact_prefix="$work/artifacts/$t-" -print_final_stats=1 "$@"
}

case "$mode" in
  short)
    seconds="${FUZZ_SECONDS:-12}"
    for t in "${all_targets[@]}"; do
      # Past crashes first: each input once (they also live on as unit tests).
      if compgen -G "$here/regressions/$t/*" >/dev/null; then
        echo "== $t: replaying tests/fuzz/regressions/$t"
        "$bin/$t" "$here/regressions/$t"/* 2>&1 | grep '^Executed'
      fi
      echo "== $t: ${seconds} s"
      log="$work/$t.log"
      if ! fuzz "$t" -max_total_time="$seconds" >"$log" 2>&1; then
        tail -n 40 "$log" >&2
        echo "fuzz target $t failed; its input is in $work/artifacts/" >&2
        exit 1
      fi
      grep -E '^(stat::number_of_executed_units|stat::new_units_added|Done)' "$log"
    done
    ;;
  long)
    runs="${FUZZ_RUNS:-10000000}"
    [ $# -gt 0 ] || set -- "${all_targets[@]}"
    for t in "$@"; do
      echo "== $t: $runs executions"
      start=$(date +%s)
      fuzz "$t" -runs="$runs" -max_total_time="${FUZZ_MAX_SECONDS:-0}"
      echo "== $t: $(($(date +%s) - start)) s"
    done
    ;;
  *)
    echo "usage: run.sh [short | long TARGET...]" >&2
    exit 2
    ;;
esac
