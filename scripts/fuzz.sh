#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/) in the checked build (build-sanitize/, see
# scripts/checked-build.sh) and runs each for a while from its committed seed corpus
# (fuzz/corpus/TARGET). A crash, a sanitizer report or a leak fails.
#   scripts/fuzz.sh [SECONDS_PER_TARGET]   (default 45; CI runs it through scripts/test.sh --fuzz)
# New interesting inputs go to build-sanitize/corpus/TARGET (not committed); a failing input is
# written to build-sanitize/artifacts/ and should become a regression test.
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo"
seconds="${1:-45}"
# MATLAS_FUZZ_TARGETS narrows the list (CI leaves out api: it needs the whole library built again).
read -r -a targets <<< "${MATLAS_FUZZ_TARGETS:-merl model request api}"
source scripts/checked-build.sh
dir=$checked_build_dir
[[ -f "$dir/CMakeCache.txt" ]] && grep -q "^MATLAS_FUZZ:BOOL=ON" "$dir/CMakeCache.txt" || configure_checked_build
cmake --build "$dir" -j "$(nproc)" --target "${targets[@]/#/fuzz_}" | tail -n 1
mkdir -p "$dir/artifacts"
status=0
for t in "${targets[@]}"; do
  mkdir -p "$dir/corpus/$t"
  echo "fuzz: $t for ${seconds} s" >&2
  if ! ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1 UBSAN_OPTIONS=print_stacktrace=1 \
       "$dir/fuzz/fuzz_$t" -max_total_time="$seconds" -rss_limit_mb=4096 -max_len=262144 -timeout=20 \
       -print_final_stats=1 -artifact_prefix="$dir/artifacts/$t-" \
       "$dir/corpus/$t" "fuzz/corpus/$t" 2> "$dir/fuzz_$t.log"; then
    echo "fuzz: $t FAILED ($dir/fuzz_$t.log, $dir/artifacts/):" >&2
    tail -n 40 "$dir/fuzz_$t.log" >&2
    status=1
  else
    grep -E "stat::number_of_executed_units|stat::peak_rss_mb" "$dir/fuzz_$t.log" | tr '\n' ' ' >&2
    echo >&2
  fi
done
exit $status
