#!/usr/bin/env bash
# Two sessions in one place (map files), as a markdown table: session 1 (the first lap) is run and
# saved (--save-map), session 2 (the second lap) loads it (--load-map), and one run over both laps
# is the yardstick. Per sequence: the frame session 2 relocalised in the loaded map at (frames after
# its start), its keyframe ATE scored with session 1's Sim(3) alignment (dsm eval --alignment-from:
# no alignment of its own, the loaded map's frame and scale), the one-run keyframe ATE over both
# laps, their ratio, and the points session 2 added against those it loaded. Then session 2 again,
# localising in the map (--localize --save-map): its ATE scored the same way and its ratio, whether
# the map file it wrote is the loaded one byte for byte, and its real-time factor in the default
# (free) pace, measured after the other runs, one run at a time. All other runs --sequential.
#
# Sequences: the two-lap synthetic scenes loop, exposure and orbit (split at their half), the shared
# EuRoC frames (0-169, 170-339) and the shared path-traced room (blender_room_s3, then
# blender_room_s3_lap2; the one run reads both laps from a folder of links).
#
# Usage: ./scripts/sessions.sh [--jobs N] [--seeds "1 2 3 4 5"] [--sequences "loop exposure orbit euroc room"]
#                              [--work DIR] [--section NAME]
#        ./scripts/sessions.sh --print-header   the table's header alone (no build, no run)
#   DSM_BIN=path   this dsm binary (no set-up or build); DSM_SHARED_DATA_DIR (default ../shared/data)
# Renders are kept in the work folder (default /tmp/dsm_sessions) and reused; runs are redone. The
# table is also written to docs/results.md (section `sessions`, scripts/results.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
RESULTS_COLUMNS=("sequence" "runs" "relocalised after (frames)" "session 2 KF ATE in session 1's alignment (mm)" "one run KF ATE (mm)" "ratio" "points added / loaded" "ratio per seed" "localised KF ATE (mm)" "localised ratio" "map unchanged" "localised real-time factor")
source scripts/results.sh
RESULTS_ARGS=$(results_args "$@")

JOBS=1
SEEDS="1 2 3 4 5"
SEQUENCES="loop exposure orbit euroc room"
WORK=/tmp/dsm_sessions
SECTION=sessions
while (($#)); do
  case "$1" in
    --jobs) JOBS="$2"; shift 2 ;;
    --seeds) SEEDS="$2"; shift 2 ;;
    --sequences) SEQUENCES="$2"; shift 2 ;;
    --work) WORK="$2"; shift 2 ;;
    --section) SECTION="$2"; shift 2 ;;
    *) echo "sessions: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
source scripts/dsm_binary.sh
DATA="$(cd "${DSM_SHARED_DATA_DIR:-../shared/data}" && pwd)"
mkdir -p "$WORK"

# The room's two laps as one recording: the EuRoC layout with both laps' images and rows.
both_room_laps() {
  local dir="$WORK/room_both/mav0" lap
  [ -f "$dir/cam0/data.csv" ] && return
  mkdir -p "$dir/cam0/data" "$dir/state_groundtruth_estimate0"
  cp "$DATA/blender_room_s3/mav0/cam0/sensor.yaml" "$dir/cam0/"
  head -n 1 "$DATA/blender_room_s3/mav0/cam0/data.csv" >"$dir/cam0/data.csv"
  head -n 1 "$DATA/blender_room_s3/mav0/state_groundtruth_estimate0/data.csv" >"$dir/state_groundtruth_estimate0/data.csv"
  for lap in blender_room_s3 blender_room_s3_lap2; do
    ln -sf "$DATA/$lap/mav0/cam0/data/"*.png "$dir/cam0/data/"
    tail -n +2 "$DATA/$lap/mav0/cam0/data.csv" >>"$dir/cam0/data.csv"
    tail -n +2 "$DATA/$lap/mav0/state_groundtruth_estimate0/data.csv" >>"$dir/state_groundtruth_estimate0/data.csv"
  done
}

# One job per line: "name both-dataset session1-dataset session1-args session2-dataset session2-args".
jobs_list=()
for s in $SEQUENCES; do
  case "$s" in
    euroc)
      jobs_list+=("euroc|$DATA/euroc_mh01_shake|$DATA/euroc_mh01_shake|--end 170|$DATA/euroc_mh01_shake|--start 170") ;;
    room)
      both_room_laps
      jobs_list+=("room|$WORK/room_both|$DATA/blender_room_s3||$DATA/blender_room_s3_lap2|") ;;
    *)
      for seed in $SEEDS; do
        seq="$WORK/seq_${s}_seed$seed"
        [ -d "$seq" ] || "$DSM" synth --scene "$s" --seed "$seed" --out "$seq" >/dev/null
        half=$(($(grep -vc "^#" "$seq/times.txt") / 2))
        jobs_list+=("${s}_seed$seed|$seq|$seq|--end $half|$seq|--start $half")
      done ;;
  esac
done

run_job() {
  IFS='|' read -r name both d1 a1 d2 a2 <<<"$1"
  local out="$WORK/run_$name"
  rm -rf "$out"
  mkdir -p "$out"
  # shellcheck disable=SC2086  # the argument lists
  {
    "$DSM" run "$both" --sequential --quiet --no-report --out "$out/both" &&
      "$DSM" run "$d1" $a1 --sequential --quiet --no-report --out "$out/s1" --save-map "$out/s1.dsmmap" &&
      "$DSM" run "$d2" $a2 --sequential --quiet --no-report --out "$out/s2" --load-map "$out/s1.dsmmap" &&
      "$DSM" eval --ref "$d2" --est "$out/s2/keyframes.tum" --alignment-from "$out/s1/eval.json" \
        --json "$out/s2_in_s1.json" &&
      "$DSM" run "$d2" $a2 --sequential --quiet --no-report --out "$out/loc" --load-map "$out/s1.dsmmap" \
        --localize --save-map "$out/loc.dsmmap" &&
      "$DSM" eval --ref "$d2" --est "$out/loc/keyframes.tum" --alignment-from "$out/s1/eval.json" \
        --json "$out/loc_in_s1.json"
  } >"$out/log" 2>&1 || echo "sessions: $name failed (see $out/log)" >&2
  if cmp -s "$out/s1.dsmmap" "$out/loc.dsmmap"; then echo true >"$out/unchanged"; else echo false >"$out/unchanged"; fi
  # Session 2's first frame, which the relocalisation's frame counts from.
  echo "${a2#--start }" | grep -Eo '^[0-9]+$' >"$out/start" || echo 0 >"$out/start"
}
export -f run_job
export DSM WORK
printf '%s\n' "${jobs_list[@]}" | xargs -P "$JOBS" -I{} bash -c 'run_job "$@"' _ {}
# The localisation's speed in the default pace, one run at a time (the others would share the cores).
for job in "${jobs_list[@]}"; do
  IFS='|' read -r name _ _ _ d2 a2 <<<"$job"
  out="$WORK/run_$name"
  [ -f "$out/s1.dsmmap" ] || continue
  # shellcheck disable=SC2086  # the argument list
  "$DSM" run "$d2" $a2 --quiet --no-report --no-map --out "$out/loc_free" --load-map "$out/s1.dsmmap" --localize \
    >>"$out/log" 2>&1 || echo "sessions: $name localised in the free pace failed (see $out/log)" >&2
done

# One row per sequence: medians over its runs (the synthetic scenes' seeds).
table() {
  results_header
  for s in $SEQUENCES; do
    rows=()
    total=0
    for out in "$WORK"/run_"$s" "$WORK"/run_"${s}"_seed*; do
      [ -d "$out" ] || continue
      case "$s" in euroc | room) [ "$out" = "$WORK/run_$s" ] || continue ;; *) [ "$out" = "$WORK/run_$s" ] && continue ;; esac
      total=$((total + 1))
      [ -f "$out/s2_in_s1.json" ] || continue
      [ -f "$out/loc_in_s1.json" ] && [ -f "$out/loc_free/stats.json" ] || continue
      rows+=("$(jq -cn --slurpfile s2 "$out/s2/stats.json" --slurpfile e "$out/s2_in_s1.json" \
        --slurpfile both "$out/both/eval.json" --argjson start "$(cat "$out/start")" \
        --slurpfile loc "$out/loc_in_s1.json" --slurpfile free "$out/loc_free/stats.json" \
        --argjson unchanged "$(cat "$out/unchanged")" '
        { reloc: ($s2[0].relocalised_in_loaded_map_at_frame | if . == null then null else . - $start end),
          ate: ($e[0].ape.rmse * 1000), both: ($both[0].keyframes.ape.rmse * 1000),
          added: $s2[0].points_added, loaded: $s2[0].map_loaded.points,
          loc: ($loc[0].ape.rmse * 1000), unchanged: $unchanged, rtf: $free[0].realtime_factor }')")
    done
    if [ ${#rows[@]} -eq 0 ]; then
      echo "| $s | 0/$total | failed | | | | | | | | | |"
      continue
    fi
    printf '%s\n' "${rows[@]}" | jq -rs --arg s "$s" --arg total "$total" '
      def median: sort | if length % 2 == 1 then .[length / 2 | floor] else (.[length / 2 - 1] + .[length / 2]) / 2 end;
      def r2: . * 100 | round / 100;
      def spread: if length == 1 then (.[0] | r2 | tostring) else "\(median | r2) [\(min | r2), \(max | r2)]" end;
      (map(.reloc) | map(select(. != null))) as $r
      | "| \($s) | \(length)/\($total) | \(if ($r | length) == 0 then "never" else "\($r | median) [max \($r | max)]" end)"
        + "\(if ($r | length) < length then " (\(length - ($r | length)) never)" else "" end)"
        + " | \(map(.ate) | spread) | \(map(.both) | spread) | \(map(.ate / .both) | spread)"
        + " | \(map(.added) | median) / \(map(.loaded) | median) | \(map(.ate / .both | r2 | tostring) | join(", "))"
        + " | \(map(.loc) | spread) | \(map(.loc / .both) | spread)"
        + " | \(map(select(.unchanged)) | length)/\(length) | \(map(.rtf) | spread) |"'
  done
}
table | results_tee "$SECTION"
