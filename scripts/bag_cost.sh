#!/usr/bin/env bash
# What reading a recording costs as it grows: the shared EuRoC frames once (340 frames, 120 MB) and
# 17 times over (5780 frames, 2 GB), as ROS 1 bags written by python3-rosbag (uncompressed and lz4
# chunks; tests/python/ros1_bags.py), as MCAP files written by @mcap/core (zstd chunks) and as
# rosbag2 SQLite bags (tests/python/ros2_recordings.py); then, for each, the time to the first frame
# (`dsm info`, which opens the recording and reads its first and last frame) and the peak memory of
# a run over its first 30 frames, timed by farm-bench against the small one, pair by pair.
#
# Usage: ./scripts/bag_cost.sh [WORK_DIR]     (default /tmp/dsm_bag_cost; ~8.5 GB of recordings,
#        kept). The ROS 2 writers need the build's tests/node (cmake --build build).
#   DSM_BAG_COST_KINDS="mcap sqlite"   measure only these (of none.bag lz4.bag mcap sqlite)
# The runs are told a global shutter (no estimate of the line delay first): they time reading.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/dsm_binary.sh
DATA="${DSM_SHARED_DATA_DIR:-../shared/data}"
WORK="${1:-/tmp/dsm_bag_cost}"
mkdir -p "$WORK"
CAM0="$DATA/euroc_mh01_shake/mav0/cam0"

for compression in none lz4; do
  for repeats in 1 17; do
    bag="$WORK/euroc_x${repeats}_${compression}.bag"
    [ -f "$bag" ] && continue
    /usr/bin/python3 - "$CAM0" "$bag" "$repeats" "$compression" <<'PY'
import pathlib, sys
sys.path.insert(0, "tests/python")
import ros1_bags as rb
import rosbag
from recordings import gray_frames
cam0, bag, repeats, compression = pathlib.Path(sys.argv[1]), sys.argv[2], int(sys.argv[3]), sys.argv[4]
rows = [l.split(",") for l in (cam0 / "data.csv").read_text().splitlines() if not l.startswith("#")]
stamps = [int(r[0]) for r in rows]
frames = gray_frames([cam0 / "data" / r[1].strip() for r in rows], 752, 480)
span = stamps[-1] - stamps[0] + 50_000_000
with rosbag.Bag(bag + ".part", "w", compression=compression) as out:
    for k in range(repeats):
        for f, t in zip(frames, stamps):
            out.write("/cam0/image_raw", rb.image_message(f, "mono8", t + k * span), t=rb.stamp(t + k * span))
pathlib.Path(bag + ".part").rename(bag)
PY
  done
done
for repeats in 1 17; do
  for container in mcap sqlite; do
    out="$WORK/euroc_x${repeats}_${container}"
    [ "$container" = mcap ] && out="$out.mcap"
    [ -e "$out" ] && continue
    DSM_NODE_TOOLS="${DSM_BUILD_DIR:-build}/tests/node" /usr/bin/python3 - "$CAM0" "$out" "$repeats" "$container" <<'PY'
import pathlib, shutil, sys
sys.path.insert(0, "tests/python")
import ros2_recordings as r2
from recordings import gray_frames
cam0, out, repeats, container = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
rows = [l.split(",") for l in (cam0 / "data.csv").read_text().splitlines() if not l.startswith("#")]
stamps = [int(r[0]) for r in rows]
frames = gray_frames([cam0 / "data" / r[1].strip() for r in rows], 752, 480)
span = stamps[-1] - stamps[0] + 50_000_000
recording = r2.Recording()
for k in range(repeats):
    for f, t in zip(frames, stamps):
        recording.add("/cam0/image_raw", "sensor_msgs/msg/Image", t + k * span, r2.image(t + k * span, 480, 752), f)
part = out.with_name(out.name + ".part")
if container == "mcap":
    recording.write_mcap(part, "zstd", chunk_size=4 << 20)
else:
    recording.write_sqlite_bag(part)
part.rename(out)
PY
  done
done
ls -l "$WORK"/*.bag "$WORK"/*.mcap

for kind in ${DSM_BAG_COST_KINDS:-none.bag lz4.bag mcap sqlite}; do
  small="$WORK/euroc_x1_${kind}"
  big="$WORK/euroc_x17_${kind}"
  [ "$kind" = mcap ] && small="$small.mcap" && big="$big.mcap"
  echo "## $kind: dsm info (open, first and last frame), 2 GB against 120 MB"
  farm-bench -n 5 --timeout 600 --vs "$DSM info $small --calib $CAM0/sensor.yaml" -- \
    "$DSM" info "$big" --calib "$CAM0/sensor.yaml"
  echo "## $kind: dsm run over the first 30 frames, 2 GB against 120 MB"
  farm-bench -n 5 --timeout 900 \
    --vs "$DSM run $small --calib $CAM0/sensor.yaml --end 30 --line-delay-us 0 --sequential --quiet --no-report --no-map --out $WORK/run_small" -- \
    "$DSM" run "$big" --calib "$CAM0/sensor.yaml" --end 30 --line-delay-us 0 --sequential --quiet --no-report --no-map --out "$WORK/run_big"
done
