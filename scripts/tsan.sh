#!/usr/bin/env bash
# ThreadSanitizer check of the two-thread paces: builds `dsm` with -fsanitize=thread in
# build-tsan/ (override with DSM_TSAN_DIR), then runs the default and the realtime pace on a
# rendered `loop` (200 frames), on a camera that leaves `loop` for `forward` and comes back (a
# second map starts and the first resumes: run/map_set.h), on the first 120 shared EuRoC frames,
# on both laps of a 600-frame `loop`: whole (the second lap's keyframes are culled), and the
# second lap localising in a map file of the first (--localize: temporary keyframes retired), and
# on `forward` at 320x240 with frames 60-129 cut out (a second map starts, recognises the first on
# the way back and takes it in: the mapping side reads the suspended map). `--workers 1` keeps the
# parallel loops on the system's own two threads (TBB's worker threads are not instrumented and
# would only produce reports about TBB itself). Fails on the first report.
# Usage: ./scripts/tsan.sh [WORK_DIR]   (default /tmp/dsm_tsan)
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh dsm >/dev/null
TSAN_DIR="${DSM_TSAN_DIR:-build-tsan}"
WORK="${1:-/tmp/dsm_tsan}"
DATA="${DSM_SHARED_DATA_DIR:-../shared/data}"
if [ ! -f "$TSAN_DIR/build.ninja" ]; then
  cmake -S . -B "$TSAN_DIR" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDSM_SANITIZE=thread \
    -DDSM_BUILD_TESTS=OFF -DDSM_BUILD_BENCHMARKS=OFF >/dev/null
fi
cmake --build "$TSAN_DIR" --target dsm -j "${DSM_JOBS:-$(nproc)}"
DSM="$TSAN_DIR/bin/dsm"
export TSAN_OPTIONS="halt_on_error=1 exitcode=66 suppressions=$PWD/scripts/tsan.supp"
mkdir -p "$WORK"
# The renderer's parallel loop runs on TBB's uninstrumented threads: not part of the check.
[ -f "$WORK/loop/groundtruth.tum" ] ||
  TSAN_OPTIONS=report_bugs=0 "$DSM" synth --scene loop --frames 200 --out "$WORK/loop" >/dev/null
[ -f "$WORK/loop600/groundtruth.tum" ] ||
  TSAN_OPTIONS=report_bugs=0 "$DSM" synth --scene loop --out "$WORK/loop600" >/dev/null
[ -f "$WORK/lap1.dsmmap" ] ||
  TSAN_OPTIONS=report_bugs=0 "$DSM" run "$WORK/loop600" --end 300 --sequential --quiet --no-report \
    --out "$WORK/run_lap1" --save-map "$WORK/lap1.dsmmap"
[ -f "$WORK/forward/times.txt" ] ||
  TSAN_OPTIONS=report_bugs=0 "$DSM" synth --scene forward --frames 90 --out "$WORK/forward" >/dev/null
[ -f "$WORK/forward_cut/times.txt" ] ||
  TSAN_OPTIONS=report_bugs=0 "$DSM" synth --scene forward --turned-textures --defects cut:60-129 --width 320 \
    --height 240 --out "$WORK/forward_cut" >/dev/null
# Frames 0-99 of `loop`, 0-89 of `forward`, 100-199 of `loop`, 50 ms apart, as one folder dataset.
if [ ! -f "$WORK/return/times.txt" ]; then
  mkdir -p "$WORK/return/images"
  cp "$WORK/loop/camera.yaml" "$WORK/return/"
  echo "# timestamp_ns exposure_ms" >"$WORK/return/times.txt"
  n=0
  for piece in "loop 0 99" "forward 0 89" "loop 100 199"; do
    read -r scene first last <<<"$piece"
    mapfile -t rows < <(grep -v '^#' "$WORK/$scene/times.txt")
    for ((i = first; i <= last; i++)); do
      name=$(printf '%06d.png' "$n")
      ln -sf "$WORK/$scene/images/$(printf '%06d.png' "$i")" "$WORK/return/images/$name"
      echo "$((1600000000000000000 + n * 50000000)) ${rows[$i]#* }" >>"$WORK/return/times.txt"
      n=$((n + 1))
    done
  done
fi
# The loop adjustment runs after a keyframe's publication while tracking goes on: every 5
# keyframes here (by default only after a relocalisation).
printf 'system: {loop_ba_min_gap: 5}\n' >"$WORK/loop_ba.yaml"
runs=("loop|$WORK/loop|" "loop_ba|$WORK/loop|--config=$WORK/loop_ba.yaml" "return|$WORK/return|")
if [ -d "$DATA/euroc_mh01_shake" ]; then runs+=("euroc|$DATA/euroc_mh01_shake|--end 120"); fi
runs+=("merge|$WORK/forward_cut|" "culling|$WORK/loop600|" "localize|$WORK/loop600|--start 300 --load-map $WORK/lap1.dsmmap --localize")
for entry in "${runs[@]}"; do
  IFS='|' read -r name dataset extra <<<"$entry"
  for pace in free realtime; do
    flag=""
    [ "$pace" = realtime ] && flag="--realtime"
    # shellcheck disable=SC2086
    "$DSM" run "$dataset" --out "$WORK/run_${name}_$pace" --quiet --workers 1 $flag $extra
    echo "tsan: $name $pace clean"
  done
done
