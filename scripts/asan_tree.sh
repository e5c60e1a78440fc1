# Sourced by `scripts/test.sh --sanitize` and `scripts/fuzz.sh`: the sanitizer tree, one for both.
# clang with AddressSanitizer + UndefinedBehaviorSanitizer; the readers' libraries also carry
# libFuzzer's coverage instrumentation (fuzz/CMakeLists.txt), so that the same objects link into
# the unit tests, dsm and the fuzzers.
#   asan_configure          installs clang and its runtime when missing, (re)configures $ASAN_DIR
#   asan_build TARGET...    builds those targets
ASAN_DIR="${DSM_ASAN_DIR:-build-asan}"
ASAN_JOBS="${DSM_JOBS:-$(nproc)}"
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"

asan_configure() {
  ./scripts/packages.sh clang libclang-rt-14-dev
  if [ -f "$ASAN_DIR/CMakeCache.txt" ] && ! grep -q '^DSM_FUZZ:BOOL=ON' "$ASAN_DIR/CMakeCache.txt"; then
    echo "sanitize: $ASAN_DIR is another kind of tree (g++ or no fuzzers); starting it afresh"
    rm -rf "$ASAN_DIR"
  fi
  # Configured every time, also a tree that exists: the test list read from it must include tests
  # added since it was last built.
  CC=clang CXX=clang++ cmake -S . -B "$ASAN_DIR" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only" \
    -DDSM_SANITIZE=address,undefined -DDSM_FUZZ=ON -DDSM_BUILD_BENCHMARKS=OFF >/dev/null
}

asan_build() {
  cmake --build "$ASAN_DIR" -j "$ASAN_JOBS" --target "$@"
}

# The fuzz targets, as fuzz/CMakeLists.txt lists them (the list may span lines).
fuzz_targets() {
  awk '/^set\(DSM_FUZZ_TARGETS/ { on = 1; sub(/^set\(DSM_FUZZ_TARGETS/, "") }
       on { done = sub(/\).*$/, ""); printf "%s ", $0; if (done) exit }' fuzz/CMakeLists.txt |
    tr -s ' ' | sed 's/^ //; s/ $//'
}
