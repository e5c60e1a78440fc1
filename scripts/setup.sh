#!/usr/bin/env bash
# Installs the Debian 12 packages dsm needs (only those missing; quiet when all are present), then
# configures and builds an optimised tree in build/ (override with DSM_BUILD_DIR).
#
# Usage: ./scripts/setup.sh [TARGET ...]
#   no target: every target (tests, benchmarks, the Python module), with the packages the tests
#              run as well (pytest, numpy, ffmpeg, chromium)
#   targets:   those alone (e.g. `dsm`, as scripts/demo.sh builds it), with the packages the build
#              needs; the tree is configured as for the whole build, so a later full build only
#              adds what is missing
set -euo pipefail
cd "$(dirname "$0")/.."

BUILD_PACKAGES=(
  g++ cmake ninja-build pkg-config
  libeigen3-dev
  libopencv-core-dev libopencv-imgproc-dev libopencv-imgcodecs-dev libopencv-features2d-dev libopencv-calib3d-dev libopencv-video-dev libopencv-videoio-dev
  libopencv-contrib-dev                        # the aruco module: ChArUco boards (dsm calibrate)
  libbz2-dev liblz4-dev libzstd-dev            # recordings' compressed chunks (bag/decompress.h)
  libsqlite3-dev                               # ROS 2 bags' .db3 files (bag/sqlite_bag.h)
  libboost-dev libwebsocketpp-dev
  libyaml-cpp-dev libcli11-dev nlohmann-json3-dev libtbb-dev libzip-dev zlib1g-dev libceres-dev
  libgtest-dev libgmock-dev libbenchmark-dev   # found when the tree is configured
  python3-dev pybind11-dev                     # the Python module
  nodejs                                       # the report page's build (npm: three.js, esbuild)
)
TEST_PACKAGES=(
  jq                                           # scripts/benchmark.sh, defects.sh, ablation.sh
  python3 python3-pytest python3-numpy ffmpeg  # Python tests (tests/python), video test input
  chromium                                     # the report page's browser test
  python3-rosbag python3-sensor-msgs python3-geometry-msgs python3-nav-msgs python3-tf2-msgs
                                               # ROS 1 bags written by ROS's own writer (tests/bags)
)

if (($#)); then
  ./scripts/packages.sh "${BUILD_PACKAGES[@]}"
else
  ./scripts/packages.sh "${BUILD_PACKAGES[@]}" "${TEST_PACKAGES[@]}"
fi
# Debian's own nodejs comes without npm (a nodejs built by NodeSource has it).
command -v npm >/dev/null || ./scripts/packages.sh npm

BUILD_DIR="${DSM_BUILD_DIR:-build}"
JOBS="${DSM_JOBS:-$(nproc)}"
if [ ! -f "$BUILD_DIR/build.ninja" ]; then
  cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
if (($#)); then
  cmake --build "$BUILD_DIR" -j "$JOBS" --target "$@"
else
  cmake --build "$BUILD_DIR" -j "$JOBS"
fi
