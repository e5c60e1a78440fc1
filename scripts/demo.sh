#!/usr/bin/env bash
# Set-up, build and the main job on the built-in input: renders the synthetic `loop` scene (a
# furnished room walked around twice) and shows what `dsm info` reads from it.
# Usage: ./scripts/demo.sh [OUT_DIR]   (default demo_out/)
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
BUILD_DIR="${DSM_BUILD_DIR:-build}"
DSM="$BUILD_DIR/bin/dsm"
OUT="${1:-demo_out}"
"$DSM" synth --scene loop --out "$OUT/loop"
"$DSM" info "$OUT/loop"
echo "demo: the sequence is in $OUT/loop (images/, camera.yaml, times.txt, groundtruth.tum)"
