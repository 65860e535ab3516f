#!/usr/bin/env bash
# Runs every test: the GoogleTest suites (ctest) on the Release build, then the browser tests of
# the web UI (Playwright driving Debian's Chromium). Run scripts/setup.sh first.
#   scripts/test.sh              all tests
#   scripts/test.sh --sanitize   also the numerical core's suites (core, brdf, formats, gp, manifold) built
#                                with ASan/UBSan in build-sanitize/ (setup.sh --sanitize configures it)
#   scripts/test.sh --fuzz       also a short fuzzing run of every libFuzzer target (scripts/fuzz.sh;
#                                MATLAS_FUZZ_SECONDS per target, default 30)
# The flags combine (CI: --sanitize --fuzz).
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo"
sanitize=0
fuzz=0
for arg in "$@"; do
  case "$arg" in
    --sanitize) sanitize=1 ;;
    --fuzz) fuzz=1 ;;
    *) echo "test: unknown option $arg" >&2; exit 2 ;;
  esac
done

[[ -x build/matlas ]] || { echo "test: build/matlas is missing: run scripts/setup.sh first" >&2; exit 1; }

jobs=$(nproc)
# Tests that use the installed environment maps and meshes find them here (setup.sh installs them).
[[ -d assets ]] && export MATLAS_ASSETS="$repo/assets"
cmake --build build -j "$jobs"
ctest --test-dir build --output-on-failure -j "$jobs"

if ((sanitize)); then
  suites=(core brdf formats gp manifold)
  targets=()
  for s in "${suites[@]}"; do targets+=("matlas_${s}_tests"); done
  cmake --build build-sanitize -j "$jobs" --target "${targets[@]}" | tail -n 2
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --test-dir build-sanitize --output-on-failure -j "$jobs" -L "^($(IFS='|'; echo "${suites[*]}"))\$" \
          -E '^(RealRgl|MixedFormats\.AFolderOfMerlAndRglFilesBuildsOneMap)$'
  # ^ minutes of resampling quadrature under ASan (../shared's files; a folder of RGL files built
  #   into a map: 148 s alone); both run in the Release suite above
fi

if ((fuzz)); then
  scripts/fuzz.sh "${MATLAS_FUZZ_SECONDS:-30}"
fi

# Browser tests: Playwright (playwright-core) drives Debian's Chromium against `matlas demo`.
web/run-browser-tests.sh build/matlas
