#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/) with clang in build-fuzz/ and runs each for a while from
# its committed seed corpus (fuzz/corpus/TARGET). A crash, a sanitizer report or a leak fails.
#   scripts/fuzz.sh [SECONDS_PER_TARGET]   (default 45; CI runs it through scripts/test.sh --fuzz)
# New interesting inputs go to build-fuzz/corpus/TARGET (not committed); a failing input is
# written to build-fuzz/artifacts/ and should become a regression test.
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo"
seconds="${1:-45}"
cxx="$(command -v clang++-14 || command -v clang++ || true)"
[[ -n "$cxx" ]] || { echo "fuzz: clang is missing: run scripts/setup.sh" >&2; exit 1; }
# MATLAS_FUZZ_TARGETS narrows the list (api needs the whole library built again with clang).
read -r -a targets <<< "${MATLAS_FUZZ_TARGETS:-merl model request api mesh scene bsdf coefficients basis samples}"
# MATLAS_CMAKE_ARGS: as in setup.sh (CI: a unity build).
# shellcheck disable=SC2086
# -O1: fuzzing needs coverage and sanitizers more than speed, and the build is faster.
cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=None -DCMAKE_CXX_FLAGS="-O1 -gline-tables-only" \
      -DCMAKE_CXX_COMPILER="$cxx" -DMATLAS_FUZZ=ON -DMATLAS_BUILD_TESTS=OFF -DMATLAS_BUILD_BENCH=OFF \
      ${MATLAS_CMAKE_ARGS:-} > /dev/null
cmake --build build-fuzz -j "$(nproc)" --target "${targets[@]/#/fuzz_}" | tail -n 1
mkdir -p build-fuzz/artifacts
status=0
for t in "${targets[@]}"; do
  mkdir -p "build-fuzz/corpus/$t"
  echo "fuzz: $t for ${seconds} s" >&2
  if ! ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1 UBSAN_OPTIONS=print_stacktrace=1 \
       "build-fuzz/fuzz/fuzz_$t" -max_total_time="$seconds" -rss_limit_mb=4096 -max_len=262144 -timeout=20 \
       -print_final_stats=1 -artifact_prefix="build-fuzz/artifacts/$t-" \
       "build-fuzz/corpus/$t" "fuzz/corpus/$t" 2> "build-fuzz/fuzz_$t.log"; then
    echo "fuzz: $t FAILED (build-fuzz/fuzz_$t.log, build-fuzz/artifacts/):" >&2
    tail -n 40 "build-fuzz/fuzz_$t.log" >&2
    status=1
  else
    grep -E "stat::number_of_executed_units|stat::peak_rss_mb" "build-fuzz/fuzz_$t.log" | tr '\n' ' ' >&2
    echo >&2
  fi
done
exit $status
