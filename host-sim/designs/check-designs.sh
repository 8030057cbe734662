#!/usr/bin/env bash
# The certified designs of the real vehicle presets, checked end to end (README, "Flying it on
# your quadrotor"). For each preset: `host-sim design` (default budget and seed), a 1000-run
# campaign of the design on the rotor plant, and a 200-run campaign with the vehicle's motor
# time constant doubled in which "converged" also asks the attitude error to stay below 1 degree
# over the last 5 s (no limit cycle). Prints one Markdown table row per preset.
#
# Usage: bash host-sim/designs/check-designs.sh [OUT_DIR] [PRESET ...]
# With REUSE_DESIGNS=1, a preset whose OUT_DIR/<preset>/design.json exists is not designed again
# (its campaigns are re-run, the design time is the one design.json recorded): to check the
# committed designs, `REUSE_DESIGNS=1 bash host-sim/designs/check-designs.sh host-sim/designs`.
# (default OUT_DIR out/designs, presets crazyflie-2.1 hummingbird x500). Every preset is designed
# with `design`'s defaults (both attitude laws and both headings searched, the norm-saturated, velocity-limited
# position feedback, airmode, the vertical channel apart and the envelope design's local regime,
# 30 s runs): four to ten minutes of design and a few seconds of campaigns per preset on 2 cores,
# after the release build. Where no design converges on 30 s runs, `design` designs again for the
# same path with the heading held (the x500), then on 300 s runs (docs/design.md), and says so.
set -euo pipefail
cd "$(dirname "$0")/../.."
out="${1:-out/designs}"
shift || true
presets=("$@")
[ ${#presets[@]} -gt 0 ] || presets=(crazyflie-2.1 hummingbird x500)

cargo build --release -p host-sim
target_dir="${CARGO_TARGET_DIR:-target}"
bin="$target_dir/release/host-sim"

rows=()
for p in "${presets[@]}"; do
  vehicle="host-sim/vehicles/$p.toml"
  dir="$out/$p"
  printf '\n==> %s: design\n' "$p"
  if [ "${REUSE_DESIGNS:-0}" = 1 ] && [ -f "$dir/design.json" ]; then
    printf '(reusing %s/design.json)\n' "$dir"
    design_s=$(python3 -c 'import json, sys; print(round(json.load(open(sys.argv[1]))["wall_time_s"]))' "$dir/design.json")
  else
    start=$(date +%s)
    "$bin" design --vehicle "$vehicle" --out "$dir"
    design_s=$(( $(date +%s) - start ))
  fi
  tau=$(awk -F'=' '/^motor_time_constant_s/ {gsub(/[ #].*/, "", $2); print $2; exit}' <(sed 's/ //g' "$vehicle"))
  doubled=$(awk -v t="$tau" 'BEGIN { printf "%.6g", 2 * t }')
  printf '\n==> %s: 1000 runs on the rotor plant\n' "$p"
  "$bin" campaign --scenario "$dir/scenario.toml" --plant rotors --runs 1000 --no-plots \
    --out "$dir/campaign"
  printf '\n==> %s: 200 runs with the motor time constant doubled (%s s)\n' "$p" "$doubled"
  "$bin" campaign --scenario "$dir/scenario.toml" --plant rotors --runs 200 --no-plots \
    --motor-time-constant-s "$doubled" --converged-attitude-deg 1 --out "$dir/campaign-doubled-lag"
  rows+=("$(python3 - "$dir" "$design_s" <<'PY'
import json, sys
d, design_s = sys.argv[1], sys.argv[2]
design = json.load(open(f"{d}/design.json"))
c = json.load(open(f"{d}/campaign/campaign.json"))
c2 = json.load(open(f"{d}/campaign-doubled-lag/campaign.json"))
r, r2 = c["results"], c2["results"]
g, ref = design["gains"], design["reference"]
obj, mar = design["objective"], design["margins"]
t_lo, t_hi, tau = design["a_priori"]
# The certified thrust interval: Theorem 1's, or [T_floor, T_max] with the no-dive thrust.
t_lo, t_hi = design.get("thrust", {}).get("interval_N", [t_lo, t_hi])
w = r["worst"]
helix = ref["certified"]["frequency_rad_s"]
fmt = lambda x, f="{:.2f}": "–" if x is None else f.format(x)
cells = [
    design["vehicle"],
    "yes" if design["certificate"]["all_hold"] else "NO",
    f'{design["rotor_fit"]["margin"] * 100:.1f} %',
    f'{g["M_p"]:.2f} m/s², ι = {design["feedback_torque_Nm"][1]:.3g} N m',
    f'{helix:.3f} rad/s' + (f' (× {ref["scale"]:.3f} of the request)' if ref["scaled"] else "")
    + (" (heading held)" if ref.get("heading_held") else ""),
    f'{design["thrust"]["mode"]}' + (f', floor {design["thrust"]["floor_N"]:.3g} N' if design["thrust"]["floor_N"] > 0 else ""),
    " / ".join(fmt(t["step_settling_time_s"], "{:.1f}") for t in obj["nominal_tasks"]) + " s",
    " / ".join(fmt(t["tilt_settling_time_s"], "{:.1f}") for t in obj["nominal_tasks"]) + " s",
    fmt(obj["altitude_loss_upside_down_m"], "{:.1f} m"),
    fmt(obj["worst_settling_180_s"], "{:.1f} s"),
    fmt(mar["motor_time_constant_max_converging_s"], "{:.3f} s") + f' (own {mar["motor_time_constant_s"]} s)',
    f'{c["duration_s"]:.0f} s',
    f'{r["fraction_converged"] * 100:.1f} %',
    f'{r2["fraction_converged"] * 100:.1f} %',
    f'{r["nominal"]["samples_outside_a_priori"]} of {r["nominal"]["samples"]}',
    f'{r["mixer"]["nominal"]["samples_given_up"]}',
    f'T [{t_lo:.3g}, {t_hi:.3g}] vs [{w["thrust_min_N"]:.3g}, {w["thrust_max_N"]:.3g}] N; τ ({", ".join(f"{x:.2g}" for x in tau)}) vs ({", ".join(f"{x:.2g}" for x in w["torque_abs_max_Nm"])}) N m',
    f"{design_s} s",
]
print("| " + " | ".join(cells) + " |")
PY
)")
done

printf '\n| vehicle | certificate holds | rotor-fit margin (certified set) | certified authority | fastest certified helix | thrust | 1 m step settling (design / Lee / PX4-style) | 30° roll settling (design / Lee / PX4-style) | altitude lost from upside down | settling from 180° (worst of 7) | largest converging motor time constant | run length (converged: settled 5 s before its end) | converged, 1000 runs | converged, 200 runs, lag doubled, < 1° | samples outside the a-priori bounds | samples the mixer gave up | a-priori bounds vs worst observed | design time |\n'
printf '|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n'
printf '%s\n' "${rows[@]}"
