# Sourced by setup.sh, test.sh and fuzz.sh: the one checked build, build-sanitize/, shared by the
# ASan/UBSan test suites and the libFuzzer targets. It is compiled once with clang at -O1 with
# ASan, UBSan and libFuzzer's coverage instrumentation (MATLAS_FUZZ=ON), so CI builds the library
# twice (Release and checked), not three times.
checked_build_dir=build-sanitize

configure_checked_build() {
  local cxx
  cxx="$(command -v clang++-14 || command -v clang++ || true)"
  [[ -n "$cxx" ]] || { echo "checked build: clang is missing: run scripts/setup.sh" >&2; return 1; }
  # A build dir configured otherwise (an older gcc sanitizer build) is configured afresh.
  if [[ -f "$checked_build_dir/CMakeCache.txt" ]] &&
     ! grep -q "^MATLAS_FUZZ:BOOL=ON" "$checked_build_dir/CMakeCache.txt"; then
    rm -rf "$checked_build_dir"
  fi
  local launcher=()
  command -v ccache > /dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  cmake -S . -B "$checked_build_dir" -G Ninja -DCMAKE_BUILD_TYPE=None \
        -DCMAKE_CXX_FLAGS="-O1 -gline-tables-only" -DCMAKE_CXX_COMPILER="$cxx" "${launcher[@]}" \
        -DMATLAS_FUZZ=ON -DMATLAS_BUILD_TESTS=ON -DMATLAS_BUILD_BENCH=OFF -DMATLAS_PYTHON=OFF > /dev/null
}
