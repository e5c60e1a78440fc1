#!/usr/bin/env bash
# Ablation of the persistent map (paper VII-A): runs `dsm run` with one change at a time on the
# synthetic scenes and the shared EuRoC frames and prints a markdown table of keyframe ATE
# (Sim(3)), keyframes, map points, points created and PBA time per keyframe.
#
# Usage: ./scripts/ablation.sh [--jobs N] [--sequences "loop forward euroc"] [--configs "dsm sw ..."] [--work DIR]
#   configs: dsm (defaults), sw (N_c = 0), nc3, nc1, nt3, nt6, levels1, levels3, huber, huber-mad,
#            move-covisible (covisible poses optimised, as in the paper), global-ba
# Timings are per process; with --jobs > 1 the runs share the cores (default: 1 job).
set -euo pipefail
cd "$(dirname "$0")/.."

JOBS=1
SEQUENCES="loop shake forward rotation exposure euroc"
CONFIGS="dsm sw nc3 nc1 nt3 nt6 levels1 levels3 huber huber-mad move-covisible global-ba"
WORK="ablation_out"
while (($#)); do
  case "$1" in
    --jobs) JOBS="$2"; shift 2 ;;
    --sequences) SEQUENCES="$2"; shift 2 ;;
    --configs) CONFIGS="$2"; shift 2 ;;
    --work) WORK="$2"; shift 2 ;;
    *) echo "ablation: unknown argument '$1'" >&2; exit 2 ;;
  esac
done

./scripts/setup.sh >/dev/null
DSM="$(pwd)/${DSM_BUILD_DIR:-build}/bin/dsm"
DATA="$(pwd)/../shared/data"
mkdir -p "$WORK"
printf 'window:\n  optimize_covisible_poses: true\n' > "$WORK/move-covisible.yaml"

args_for() {
  case "$1" in
    dsm) echo "" ;;
    sw) echo "--mode sw" ;;
    nc3) echo "--nc 3" ;;
    nc1) echo "--nc 1" ;;
    nt3) echo "--nt 3" ;;
    nt6) echo "--nt 6" ;;
    levels1) echo "--pba-levels 1" ;;
    levels3) echo "--pba-levels 3" ;;
    huber) echo "--robust huber" ;;
    huber-mad) echo "--robust huber-mad" ;;
    move-covisible) echo "--config $WORK/move-covisible.yaml" ;;
    global-ba) echo "--global-ba" ;;
    *) echo "ablation: unknown config '$1'" >&2; exit 2 ;;
  esac
}

dataset_for() {
  if [ "$1" = euroc ]; then
    echo "$DATA/euroc_mh01_shake"
  else
    [ -d "$WORK/seq_$1" ] || "$DSM" synth --scene "$1" --out "$WORK/seq_$1" >/dev/null
    echo "$WORK/seq_$1"
  fi
}

jobs_list=()
for s in $SEQUENCES; do
  d="$(dataset_for "$s")"
  for c in $CONFIGS; do
    jobs_list+=("$DSM run $d --out $WORK/run_${s}_$c --quiet $(args_for "$c") > $WORK/run_${s}_$c.log 2>&1")
  done
done
printf '%s\n' "${jobs_list[@]}" | xargs -P "$JOBS" -I{} sh -c '{} || echo "failed: {}" >&2'

echo "| sequence | config | KF ATE (mm) | keyframes | map points | points created | PBA ms/KF (mean) |"
echo "|---|---|---|---|---|---|---|"
for s in $SEQUENCES; do
  for c in $CONFIGS; do
    out="$WORK/run_${s}_$c"
    if [ ! -f "$out/stats.json" ]; then
      echo "| $s | $c | failed | | | | |"
      continue
    fi
    ate="n/a"
    [ -f "$out/eval.json" ] && ate=$(jq -r '.keyframes.ape.rmse * 1000 | . * 100 | round / 100' "$out/eval.json")
    jq -r --arg s "$s" --arg c "$c" --arg ate "$ate" \
      '"| \($s) | \($c) | \($ate) | \(.keyframes) | \(.map_points) | \(.points_created) | \(.timing_ms.pba.mean | round) |"' \
      "$out/stats.json"
  done
done
