#!/usr/bin/env bash
# Set-up, build and the whole test suite. Extra arguments go to ctest, e.g.
#   ./scripts/test.sh -L slow      only the long end-to-end tests
#   ./scripts/test.sh -LE slow     everything else
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
BUILD_DIR="${DSM_BUILD_DIR:-build}"
cd "$BUILD_DIR"
ctest --output-on-failure -j "${DSM_JOBS:-$(nproc)}" "$@"
