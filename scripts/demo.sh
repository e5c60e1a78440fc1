#!/usr/bin/env bash
# Set-up, build and the main job on the built-in input: renders the synthetic `loop` scene (a
# furnished room walked around twice), runs SLAM on it and shows the trajectory error. Builds the
# `dsm` program alone (scripts/test.sh builds the rest) and says how long each step took.
# Usage: ./scripts/demo.sh [OUT_DIR]   (default demo_out/)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR="${DSM_BUILD_DIR:-build}"
DSM="$BUILD_DIR/bin/dsm"
OUT="${1:-demo_out}"
step() {
  local name="$1" start=$SECONDS
  shift
  "$@"
  echo "demo: $name took $((SECONDS - start)) s"
}
step "set-up and build" ./scripts/setup.sh dsm
step "rendering the scene" "$DSM" synth --scene loop --out "$OUT/loop"
"$DSM" info "$OUT/loop"
step "the run" "$DSM" run "$OUT/loop" --out "$OUT/run" --quiet
echo "demo: trajectories, stats.json, eval.json, the map (map.ply) and report.html are in $OUT/run"
