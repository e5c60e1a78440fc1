#!/usr/bin/env bash
# Speed, memory and accuracy of whole runs, as a markdown table (one row per sequence and pace):
# the shared EuRoC frames and every synthetic scene in the three paces (sequential, free: two
# threads as fast as tracking takes frames, realtime: frames released at their timestamps), and a
# long synthetic loop (20 laps, 6000 frames) in the default pace. Then the Google Benchmark kernels.
#
# Usage: ./scripts/benchmark.sh [WORK_DIR]      (default /tmp/dsm_benchmark)
#        ./scripts/benchmark.sh --print-header   the table's header alone (no build, no run)
#   DSM_BENCH_QUICK=1   only EuRoC and the loop scene, and a 1200-frame long loop
#   DSM_BENCH_LONG_FRAMES=N   the long loop's frames (default 6000; 1200 with DSM_BENCH_QUICK)
#   DSM_BENCH_NO_KERNELS=1   skip the Google Benchmark programs
#   DSM_BIN=path   measure this dsm binary (no set-up or build; e.g. a copy of an older build)
# Renders are kept in WORK_DIR and reused. Compare numbers from one invocation only: this machine's
# speed drifts from hour to hour. The output is also written to docs/results.md (scripts/results.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
RESULTS_COLUMNS=("sequence" "pace" "frames" "KF kept / made" "tracking ms median / p90" "PBA ms/KF mean / KF 100–200 / last 100" "fps" "real-time factor" "dropped" "latency ms median / p90 / p90 of the kept pose" "peak RSS MB" "KF ATE mm")
source scripts/results.sh
RESULTS_ARGS="${DSM_BENCH_QUICK:+(DSM_BENCH_QUICK=$DSM_BENCH_QUICK${DSM_BENCH_LONG_FRAMES:+ DSM_BENCH_LONG_FRAMES=$DSM_BENCH_LONG_FRAMES})}"
# The kernels' programs are built with every target.
if [ "${DSM_BENCH_NO_KERNELS:-0}" != 1 ]; then DSM_SETUP_TARGETS=""; fi
source scripts/dsm_binary.sh
DATA="${DSM_SHARED_DATA_DIR:-../shared/data}"
WORK="${1:-/tmp/dsm_benchmark}"
mkdir -p "$WORK"

SCENES=(loop forward rotation shake exposure orbit pan)
LONG_FRAMES=6000
if [ "${DSM_BENCH_QUICK:-0}" = 1 ]; then
  SCENES=(loop)
  LONG_FRAMES=1200
fi
LONG_FRAMES="${DSM_BENCH_LONG_FRAMES:-$LONG_FRAMES}"

render() {  # render SCENE DIR [synth args]
  local scene=$1 dir=$2
  shift 2
  if [ ! -f "$dir/groundtruth.tum" ]; then "$DSM" synth --scene "$scene" --out "$dir" "$@" >/dev/null; fi
}

# jq helpers: rounding; over a per-keyframe list, the mean of keyframes 100-200 ("-" with 100 or
# fewer: the long loop's bound compares them with the last 100) and of the last 100.
JQ_DEFS='
  def r(d): . * pow(10; d) | round / pow(10; d);
  def mean: if length == 0 then 0 else add / length end;
  def kf100to200(d): if length > 100 then (.[100:200] | mean | r(d)) else "-" end;
  def last100(d): .[(length - 100 | if . < 0 then 0 else . end):] | mean | r(d);
'

# One row from a run's stats.json and eval.json.
row() {  # row NAME PACE RUN_DIR
  local name=$1 pace=$2 run=$3 ate="-"
  if [ -f "$run/eval.json" ]; then ate=$(jq '.keyframes.ape.rmse * 1000 | . * 100 | round / 100' "$run/eval.json"); fi
  jq -r --arg name "$name" --arg pace "$pace" --arg ate "$ate" "$JQ_DEFS"'
    [.per_keyframe[] | .pba.ms | select(. > 0)] as $pba |
    "| \($name) | \($pace) | \(.frames)/\(.frames + .frames_dropped) | \(.keyframes_kept) / \(.keyframes) | " +
    "\(.timing_ms.tracking.median | r(1)) / \(.timing_ms.tracking.p90 | r(1)) | " +
    "\(.timing_ms.pba.mean | r(0)) / \($pba | kf100to200(0)) / \($pba | last100(0)) | " +
    "\(.frames_per_second | r(1)) | \((.realtime_factor // 0) | r(2)) | \(.frames_dropped) | " +
    "\(.latency_ms.median | r(0)) / \(.latency_ms.p90 | r(0)) / \(.latency_final_ms.p90 | r(0)) | \(.peak_rss_mb | r(0)) | \($ate) |"' "$run/stats.json"
}

run() {  # run NAME DATASET PACE
  local name=$1 dataset=$2 pace=$3 out="$WORK/run_${1}_${3}"
  "$DSM" run "$dataset" --out "$out" --quiet "--$pace" >"$out.log" 2>&1 || {
    echo "| $name | $pace | failed: see $out.log |" >&2
    return 0
  }
  row "$name" "$pace" "$out"
}
# `dsm run` has no --free flag: free is its default.
run_free() {  # run_free NAME DATASET
  local name=$1 dataset=$2 out="$WORK/run_${1}_free"
  "$DSM" run "$dataset" --out "$out" --quiet >"$out.log" 2>&1 || {
    echo "| $name | free | failed: see $out.log |" >&2
    return 0
  }
  row "$name" free "$out"
}

main() {
results_header
SEQS=()
if [ -d "$DATA/euroc_mh01_shake" ]; then SEQS+=("euroc_mh01|$DATA/euroc_mh01_shake"); fi
for s in "${SCENES[@]}"; do
  render "$s" "$WORK/seq_$s"
  SEQS+=("$s|$WORK/seq_$s")
done
for entry in "${SEQS[@]}"; do
  name=${entry%%|*}
  dataset=${entry#*|}
  run "$name" "$dataset" sequential
  run_free "$name" "$dataset"
  run "$name" "$dataset" realtime
done
render loop "$WORK/seq_loop_$LONG_FRAMES" --frames "$LONG_FRAMES"
run_free "loop_$LONG_FRAMES" "$WORK/seq_loop_$LONG_FRAMES"
# What the long loop's bundle adjustments hold, keyframes 100-200 against the last 100: counts
# that do not drift with the machine's speed, unlike the times above.
problem() {  # problem RUN_DIR
  jq -r "$JQ_DEFS"'
    [.per_keyframe[] | .pba | select(.ms > 0)] as $p |
    "\nLong loop, per bundle adjustment (keyframes 100-200 / last 100): fixed keyframes " +
    "\($p | map(.fixed_keyframes) | kf100to200(1)) / \($p | map(.fixed_keyframes) | last100(1)), " +
    "observations \($p | map(.observations) | kf100to200(0)) / \($p | map(.observations) | last100(0)), " +
    "LM iterations \($p | map(.iterations) | kf100to200(1)) / \($p | map(.iterations) | last100(1)); " +
    "keyframe pyramids rebuilt in all: \(.pyramids_rebuilt)"' "$1/stats.json"
}
if [ -f "$WORK/run_loop_${LONG_FRAMES}_free/stats.json" ]; then problem "$WORK/run_loop_${LONG_FRAMES}_free"; fi

if [ "${DSM_BENCH_NO_KERNELS:-0}" != 1 ]; then
  echo
  for b in "$BUILD_DIR"/src/dsm/*/*_benchmark; do
    [ -x "$b" ] || continue
    echo "### $(basename "$b")"
    "$b" --benchmark_min_time=0.5 2>/dev/null | grep -E "^BM_|^-|^Benchmark" || true
  done
fi
}
main | results_tee benchmark
