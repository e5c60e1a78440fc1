#!/usr/bin/env bash
# Ablation of the persistent map (paper VII-A): runs `dsm run` with one change at a time on the
# synthetic scenes and the shared EuRoC frames and prints a markdown table of keyframe ATE
# (Sim(3)), keyframes, map points, points created and PBA time per keyframe.
#
# Usage: ./scripts/ablation.sh [--jobs N] [--sequences "loop forward euroc"] [--configs "dsm sw ..."]
#                              [--seeds "1 2 3"] [--starts "0 1 2"] [--work DIR] [--section NAME] [--reuse]
#        ./scripts/ablation.sh --print-header   the table's header alone (no build, no run)
#   reuse:   a run whose stats.json is in the work folder from before is not run again (to resume
#            an interrupted ablation, or to add sequences or configs to one; same binary only)
#   section: the section of docs/results.md the table is written to (scripts/results.sh; default
#            ablation); `accuracy`, the README's results table, is
#            --configs "dsm sw" --seeds "1 2 3 4 5" --section accuracy --sequences "loop shake forward
#            rotation exposure orbit pan block twins handheld uturn swing euroc room"
#   sequences: the synthetic scenes loop shake forward rotation exposure orbit pan block twins
#            handheld uturn swing, each also as <scene>-noisy (rendered with image noise of 6 grey
#            levels instead of 1) and <scene>-rs (at 30 Hz with a rolling shutter of 30 us per row), and the
#            shared euroc (EuRoC MH01 frames) and room (path-traced blender_room_s3)
#   configs: dsm (defaults), sw (DSM-SW: N_t + N_c temporal keyframes), sw-short (DSM-SW with N_t
#            alone, as before it had the window's whole size), nc3, nc1, nt3, nt6, levels1, levels3,
#            huber, huber-mad, move-covisible (covisible poses optimised, as in the paper), global-ba,
#            no-occlusion (observations also of points hidden by nearer map points), all-reference
#            (the tracker also uses points without a verified observation in the keyframe),
#            no-noise-floor (candidates also where the gradient is at the image noise's level),
#            no-contrast-floor (candidates also where the 8-pixel pattern's contrast is at the
#            noise's level), bilinear (residuals sample noisy images bilinearly, not by the
#            B-spline), no-texture-loss (observations whose target shows no trace of the point's
#            texture stay in the error models' fits on noisy images too), free-sigma (each keyframe's
#            error model fitted without the bound on its scale), newest-model (only the newest keyframe's error model is fitted, to the
#            residuals of points hosted by free keyframes, as the original DSM:
#            pba.refit_all_models false), no-young-ba (without the whole young map's bundle
#            adjustments at 10, 20 and 40 keyframes: system.young_map_ba_last 0), no-loop-ba (without the
#            adjustment of a loop's keyframes when the covisible keyframes reach 20 keyframes back:
#            system.loop_ba_min_gap 0), no-culling
#            (every keyframe stays: system.keyframe_culling false), no-loop-closure (places seen before
#            are not recognised: --no-loop-closure), global-shutter (a rolling shutter's frames taken
#            for a global shutter's: --line-delay-us 0)
#   seeds:   each synthetic scene is rendered once per seed (textures and hand-held jitter); with
#            more than one seed a row gives the median over the seeds, the ATE also as
#            "median [min, max]", and a last column lists the ATE of every seed. Single runs of a
#            scene move by tens of percent with rounding alone, so compare variants on several seeds.
#            EuRoC has one run per config; the room walk starts at frame 2 (seed - 1) per seed (a
#            single room run moves by a factor of several with the first frame).
#   starts:  first frames (default 0): each seed's run is repeated from each, and a row gives the
#            median over seeds x starts. A run started one frame later moves by a factor of up to
#            3 (uturn, orbit, pan), so 5 seeds alone resolve differences of tens of percent at best.
#            EuRoC starts at the frame given; the room walk at 2 (seed - 1) + 10 x start.
# Timings are per process; with --jobs > 1 the runs share the cores (default: 1 job).
# DSM_BIN=path runs this dsm binary (no set-up or build).
set -euo pipefail
cd "$(dirname "$0")/.."
RESULTS_COLUMNS=("sequence" "config" "KF ATE (mm)" "keyframes" "map points" "points created" "PBA ms/KF (mean)" "runs" "ATE per seed (mm)")
source scripts/results.sh
RESULTS_ARGS=$(results_args "$@")

JOBS=1
SECTION=ablation
REUSE=0
SEEDS="1"
STARTS="0"
SEQUENCES="loop shake forward rotation exposure orbit pan euroc room"
CONFIGS="dsm sw sw-short nc3 nc1 nt3 nt6 levels1 levels3 huber huber-mad move-covisible global-ba no-occlusion all-reference no-noise-floor no-contrast-floor bilinear no-texture-loss free-sigma newest-model no-young-ba no-loop-ba"
WORK="ablation_out"
while (($#)); do
  case "$1" in
    --jobs) JOBS="$2"; shift 2 ;;
    --sequences) SEQUENCES="$2"; shift 2 ;;
    --configs) CONFIGS="$2"; shift 2 ;;
    --seeds) SEEDS="$2"; shift 2 ;;
    --starts) STARTS="$2"; shift 2 ;;
    --work) WORK="$2"; shift 2 ;;
    --section) SECTION="$2"; shift 2 ;;
    --reuse) REUSE=1; shift ;;
    *) echo "ablation: unknown argument '$1'" >&2; exit 2 ;;
  esac
done

for seed in $SEEDS; do
  [[ "$seed" =~ ^[0-9]+$ ]] || { echo "ablation: --seeds: '$seed' is not a non-negative integer" >&2; exit 2; }
done
for start in $STARTS; do
  [[ "$start" =~ ^[0-9]+$ ]] || { echo "ablation: --starts: '$start' is not a non-negative integer" >&2; exit 2; }
done

source scripts/dsm_binary.sh
DATA="$(cd "${DSM_SHARED_DATA_DIR:-../shared/data}" && pwd)"
mkdir -p "$WORK"
printf 'window:\n  optimize_covisible_poses: true\n' > "$WORK/move-covisible.yaml"
printf 'occlusion:\n  enabled: false\n' > "$WORK/no-occlusion.yaml"
printf 'tracker:\n  verified_reference: false\n' > "$WORK/all-reference.yaml"
printf 'candidates:\n  noise_factor: 0\n' > "$WORK/no-noise-floor.yaml"
printf 'candidates:\n  contrast_factor: 0\n' > "$WORK/no-contrast-floor.yaml"
printf 'system:\n  interpolation: bilinear\n' > "$WORK/bilinear.yaml"
printf 'system:\n  texture_loss_min_noise: 0\n' > "$WORK/no-texture-loss.yaml"
printf 'pba:\n  max_sigma_ratio: 0\n' > "$WORK/free-sigma.yaml"
printf 'pba:\n  refit_all_models: false\n' > "$WORK/newest-model.yaml"
printf 'system:\n  young_map_ba_last: 0\n' > "$WORK/no-young-ba.yaml"
printf 'system:\n  loop_ba_min_gap: 0\n' > "$WORK/no-loop-ba.yaml"
printf 'system:\n  keyframe_culling: false\n' > "$WORK/no-culling.yaml"

args_for() {
  case "$1" in
    dsm) echo "" ;;
    sw) echo "--mode sw" ;;
    sw-short) echo "--mode sw --nc 0" ;;
    nc3) echo "--nc 3" ;;
    nc1) echo "--nc 1" ;;
    nt3) echo "--nt 3" ;;
    nt6) echo "--nt 6" ;;
    levels1) echo "--pba-levels 1" ;;
    levels3) echo "--pba-levels 3" ;;
    huber) echo "--robust huber" ;;
    huber-mad) echo "--robust huber-mad" ;;
    move-covisible | no-occlusion | all-reference | no-noise-floor | no-contrast-floor | bilinear | no-texture-loss | free-sigma | newest-model | no-young-ba | no-loop-ba | no-culling) echo "--config $WORK/$1.yaml" ;;
    global-ba) echo "--global-ba" ;;
    no-loop-closure) echo "--no-loop-closure" ;;
    global-shutter) echo "--line-delay-us 0" ;;
    *) echo "ablation: unknown config '$1'" >&2; exit 2 ;;
  esac
}

# Runs of a sequence: "name dataset [run arguments]" per line, one per seed and start (the
# synthetic scenes are rendered once per seed; the room walk, which cannot be rendered anew, starts
# at frame 2 (seed - 1) instead).
runs_for() {
  local start suffix
  for start in $STARTS; do
    suffix=""
    [ "$start" = 0 ] || suffix="_start$start"
    runs_from "$1" "$start" "$suffix"
  done
}

runs_from() {
  local start="$2" suffix="$3"
  if [ "$1" = euroc ]; then
    echo "euroc$suffix $DATA/euroc_mh01_shake --start $start"
    return
  fi
  if [ "$1" = room ]; then
    for seed in $SEEDS; do
      local name=room
      [ "$seed" = 1 ] || name="room_seed$seed"
      echo "$name$suffix $DATA/blender_room_s3 --start $((2 * (seed - 1) + 10 * start))"
    done
    return
  fi
  local scene="$1" noise=1 shutter=()
  if [[ "$1" == *-noisy ]]; then scene="${1%-noisy}" noise=6; fi
  if [[ "$1" == *-rs ]]; then scene="${1%-rs}" shutter=(--rate 30 --rolling-shutter 30); fi
  for seed in $SEEDS; do
    local name="$1"
    [ "$seed" = 1 ] || name="$1_seed$seed"
    [ -d "$WORK/seq_$name" ] ||
      "$DSM" synth --scene "$scene" --seed "$seed" --noise "$noise" "${shutter[@]}" --out "$WORK/seq_$name" >/dev/null
    echo "$name$suffix $WORK/seq_$name --start $start"
  done
}

jobs_list=()
for s in $SEQUENCES; do
  while read -r name d extra; do
    for c in $CONFIGS; do
      [ "$REUSE" = 1 ] && [ -f "$WORK/run_${name}_$c/stats.json" ] && continue
      jobs_list+=("$DSM run $d $extra --sequential --out $WORK/run_${name}_$c --quiet $(args_for "$c") > $WORK/run_${name}_$c.log 2>&1")
    done
  done < <(runs_for "$s")
done
printf '%s\n' "${jobs_list[@]}" | xargs -P "$JOBS" -I{} sh -c '{} || echo "failed: {}" >&2'

# One row per sequence and config: medians over the runs (seeds x starts) that finished.
table() {
results_header
for s in $SEQUENCES; do
  names=$(runs_for "$s" | cut -d' ' -f1)
  for c in $CONFIGS; do
    rows=()
    for name in $names; do
      out="$WORK/run_${name}_$c"
      [ -f "$out/stats.json" ] || continue
      ate=null
      [ -f "$out/eval.json" ] && ate=$(jq '.keyframes.ape.rmse * 1000' "$out/eval.json")
      rows+=("$(jq -c --argjson ate "$ate" '{ate: $ate, kf: .keyframes, pts: .map_points, created: .points_created, pba: .timing_ms.pba.mean}' "$out/stats.json")")
    done
    total=$(echo "$names" | wc -w)
    if [ ${#rows[@]} -eq 0 ]; then
      echo "| $s | $c | failed | | | | | 0/$total | |"
      continue
    fi
    printf '%s\n' "${rows[@]}" | jq -rs --arg s "$s" --arg c "$c" --arg total "$total" '
      def median: sort | if length % 2 == 1 then .[length / 2 | floor] else (.[length / 2 - 1] + .[length / 2]) / 2 end;
      def r2: . * 100 | round / 100;
      (map(.ate) | map(select(. != null))) as $ates
      | (if ($ates | length) == 0 then "n/a"
         elif length == 1 then ($ates[0] | r2 | tostring)
         else "\($ates | median | r2) [\($ates | min | r2), \($ates | max | r2)]" end) as $ate
      | "| \($s) | \($c) | \($ate) | \(map(.kf) | median | round) | \(map(.pts) | median | round) | \(map(.created) | median | round) | \(map(.pba) | median | round) | \(length)/\($total) | \($ates | map(r2 | tostring) | join(", ")) |"'
  done
done
}
table | results_tee "$SECTION"
