# Sourced by `scripts/benchmark.sh` and `scripts/defects.sh`, from the repository's root: sets DSM,
# the dsm binary they run: $DSM_BIN when set (no set-up or build; e.g. a copy of an older build),
# else $BUILD_DIR/bin/dsm (BUILD_DIR: $DSM_BUILD_DIR, default build) after set-up and a build of
# the targets in DSM_SETUP_TARGETS (default dsm; empty: every target).
BUILD_DIR="${DSM_BUILD_DIR:-build}"
if [ -n "${DSM_BIN:-}" ]; then
  DSM="$DSM_BIN"
else
  # shellcheck disable=SC2086  # a list of targets
  ./scripts/packages.sh jq && ./scripts/setup.sh ${DSM_SETUP_TARGETS-dsm} >/dev/null
  DSM="$BUILD_DIR/bin/dsm"
fi
