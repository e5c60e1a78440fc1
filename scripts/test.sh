#!/usr/bin/env bash
# Set-up, build and the whole test suite. Extra arguments go to ctest, e.g.
#   ./scripts/test.sh -L slow      only the long end-to-end tests
#   ./scripts/test.sh -LE slow     everything else
#   ./scripts/test.sh --sanitize   AddressSanitizer + UndefinedBehaviorSanitizer (clang): builds
#                                  build-asan/ (DSM_ASAN_DIR; scripts/asan_tree.sh), runs the unit
#                                  tests and one short end-to-end run of a rendered scene with
#                                  defects (lost frames, relocalisation); fails on any report
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
if [ "${1:-}" = "--sanitize" ]; then
  shift
  source scripts/asan_tree.sh
  asan_configure
  # The programs of the unit tests (ctest name a/b is target a_b) and dsm; not the long end-to-end
  # tests' programs.
  unit=$(cd "$ASAN_DIR" && ctest -N -LE slow | sed -n 's/.*Test *#[0-9]*: //p' | tr / _)
  asan_build dsm $unit
  (cd "$ASAN_DIR" && ctest --output-on-failure -j "$ASAN_JOBS" -LE slow "$@")
  work="$(mktemp -d)"
  trap 'rm -rf "$work"' EXIT
  "$ASAN_DIR/bin/dsm" synth --scene loop --frames 160 --out "$work/loop" \
    --defects black:60-66,noise:80-84,corrupt:90,cover:110-125 >/dev/null
  "$ASAN_DIR/bin/dsm" run "$work/loop" --sequential --quiet --out "$work/out"
  echo "sanitize: unit tests and the end-to-end run clean"
  exit 0
fi
BUILD_DIR="${DSM_BUILD_DIR:-build}"
cd "$BUILD_DIR"
ctest --output-on-failure -j "${DSM_JOBS:-$(nproc)}" "$@"
