# Sourced by `scripts/benchmark.sh` and `scripts/defects.sh`, from the repository's root: sets DSM,
# the dsm binary they run: $DSM_BIN when set (no set-up or build; e.g. a copy of an older build),
# else $BUILD_DIR/bin/dsm (BUILD_DIR: $DSM_BUILD_DIR, default build) after set-up and build.
BUILD_DIR="${DSM_BUILD_DIR:-build}"
if [ -n "${DSM_BIN:-}" ]; then
  DSM="$DSM_BIN"
else
  ./scripts/packages.sh jq && ./scripts/setup.sh dsm >/dev/null
  DSM="$BUILD_DIR/bin/dsm"
fi
