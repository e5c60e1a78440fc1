#!/usr/bin/env bash
# Set-up, build and the main job on the built-in input: renders the synthetic `loop` scene (a
# furnished room walked around twice), runs SLAM on it and shows the trajectory error.
# Usage: ./scripts/demo.sh [OUT_DIR]   (default demo_out/)
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
BUILD_DIR="${DSM_BUILD_DIR:-build}"
DSM="$BUILD_DIR/bin/dsm"
OUT="${1:-demo_out}"
"$DSM" synth --scene loop --out "$OUT/loop"
"$DSM" info "$OUT/loop"
"$DSM" run "$OUT/loop" --out "$OUT/run" --quiet
echo "demo: trajectories, stats.json, eval.json, the map (map.ply) and report.html are in $OUT/run"
