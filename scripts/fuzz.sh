#!/usr/bin/env bash
# Fuzzes every reader of user files for SECONDS each (default 60), with libFuzzer, as many targets
# at a time as there are cores:
#   ./scripts/fuzz.sh [SECONDS]
# The targets (fuzz/*_fuzz.cc) build in the sanitizer tree (scripts/asan_tree.sh: clang, ASan +
# UBSan). Each starts from its seeds (fuzz/seeds/<target>), the kept crash inputs
# (fuzz/regressions/<target>), seeds cut from the test data (the shared EuRoC-layout sequences and
# trajectories, a rendered scene) and the corpus that earlier runs grew (<tree>/fuzz-corpus).
# A crash, sanitizer report, hang (10 s) or broken promise fails the run; its input is copied to
# fuzz/regressions/<target>/ (fix the bug: ctest then replays it) and printed in hex.
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_EACH="${1:-60}"
if ! [[ "$SECONDS_EACH" =~ ^[0-9]+$ ]] || [ "$SECONDS_EACH" -lt 1 ]; then
  echo "usage: scripts/fuzz.sh [SECONDS]  (SECONDS: a positive whole number, got '$SECONDS_EACH')" >&2
  exit 2
fi
source scripts/asan_tree.sh
asan_configure
read -r -a targets <<<"$(fuzz_targets)"
if [ "${#targets[@]}" -eq 0 ]; then
  echo "fuzz: no targets found in fuzz/CMakeLists.txt (set(DSM_FUZZ_TARGETS ...))" >&2
  exit 1
fi
asan_build dsm $(printf '%s_fuzz ' "${targets[@]}")

work="$ASAN_DIR/fuzz-work"
rm -rf "$work"
mkdir -p "$work"
shared="${DSM_SHARED_DATA:-../shared/data}"

# Seeds from the test data: a file's first lines, behind the digit that picks its place in the
# target's layout (see the target's source).
seed() {  # seed TARGET NAME DIGIT FILE
  [ -f "$4" ] || return 0
  mkdir -p "$work/seeds/$1"
  { printf '%s\n' "$3"; head -n 12 "$4"; } >"$work/seeds/$1/$2"
}
for mav0 in "$shared"/*/mav0; do
  [ -d "$mav0/cam0" ] || continue
  name=$(basename "$(dirname "$mav0")")
  seed euroc_dataset "$name-sensor" 0 "$mav0/cam0/sensor.yaml"
  seed euroc_dataset "$name-images" 1 "$mav0/cam0/data.csv"
  seed euroc_dataset "$name-gt" 2 "$mav0/state_groundtruth_estimate0/data.csv"
  seed trajectory "$name-gt" 1 "$mav0/state_groundtruth_estimate0/data.csv"
done
for f in "$shared"/trajectories/*; do
  [ -f "$f" ] || continue
  name=$(basename "$f")
  seed trajectory "$name-detect" 3 "$f"
  case "$name" in
    *.csv) seed trajectory "$name" 1 "$f" ;;
    KITTI*) seed trajectory "$name" 2 "$f"; seed kitti_dataset "$name" 2 "$f" ;;
    *) seed trajectory "$name" 0 "$f"; seed tum_dataset "$name" 4 "$f" ;;
  esac
done
"$ASAN_DIR/bin/dsm" synth --scene loop --frames 3 --width 96 --height 64 --out "$work/scene" >/dev/null
seed folder_dataset scene-camera 0 "$work/scene/camera.yaml"
seed folder_dataset scene-times 1 "$work/scene/times.txt"
seed folder_dataset scene-gt 2 "$work/scene/groundtruth.tum"
seed trajectory scene-gt 0 "$work/scene/groundtruth.tum"
# A map file of a few keyframes, made by a short run on a small rendering.
"$ASAN_DIR/bin/dsm" synth --scene loop --frames 30 --width 128 --height 96 --out "$work/map_scene" >/dev/null
mkdir -p "$work/seeds/map_file"
"$ASAN_DIR/bin/dsm" run "$work/map_scene" --sequential --quiet --no-report --no-map --out "$work/map_run" \
  --save-map "$work/seeds/map_file/small.dsmmap" >/dev/null

fuzz_one() {  # fuzz_one TARGET: runs it, prints one line, returns non-zero on a finding
  local t=$1
  local corpus="$ASAN_DIR/fuzz-corpus/$t" crashes="$work/crashes/$t"
  mkdir -p "$corpus" "$crashes"
  local dirs=("$corpus" "fuzz/seeds/$t")
  [ -d "fuzz/regressions/$t" ] && dirs+=("fuzz/regressions/$t")
  [ -d "$work/seeds/$t" ] && dirs+=("$work/seeds/$t")
  local dict=fuzz/text.dict
  [ "$t" = encoded_image ] && dict=fuzz/image.dict
  local rc=0
  "$ASAN_DIR/fuzz/${t}_fuzz" -max_total_time="$SECONDS_EACH" -timeout=10 -dict="$dict" -use_value_profile=1 \
    -print_final_stats=1 -artifact_prefix="$crashes/" "${dirs[@]}" >"$work/$t.log" 2>&1 || rc=$?
  local runs
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$work/$t.log" | tail -1)
  if [ "$rc" -eq 0 ]; then
    echo "fuzz: $t: ${runs:-?} inputs in ${SECONDS_EACH} s, no finding"
    return 0
  fi
  echo "fuzz: $t: FAILED (exit $rc) after ${runs:-?} inputs; log $work/$t.log"
  grep -m1 -E "ERROR|runtime error|Check failed|terminate called" "$work/$t.log" || true
  for f in "$crashes"/*; do
    [ -f "$f" ] || continue
    mkdir -p "fuzz/regressions/$t"
    cp "$f" "fuzz/regressions/$t/"
    echo "fuzz: $t: input kept as fuzz/regressions/$t/$(basename "$f"); replay: $ASAN_DIR/fuzz/${t}_fuzz $f"
    head -c 2048 "$f" | od -A d -t x1z | head -n 40
  done
  return 1
}

echo "fuzz: ${#targets[@]} targets, ${SECONDS_EACH} s each, ${ASAN_JOBS} at a time"
failed=0
running=0
for t in "${targets[@]}"; do
  fuzz_one "$t" &
  running=$((running + 1))
  if [ "$running" -ge "$ASAN_JOBS" ]; then
    wait -n || failed=1
    running=$((running - 1))
  fi
done
while [ "$running" -gt 0 ]; do
  wait -n || failed=1
  running=$((running - 1))
done
if [ "$failed" -ne 0 ]; then
  echo "fuzz: findings above"
  exit 1
fi
echo "fuzz: all ${#targets[@]} targets ran ${SECONDS_EACH} s without a finding"
