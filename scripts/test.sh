#!/usr/bin/env bash
# Runs every test: the GoogleTest suites (ctest) on the Release build, then the browser tests of
# the web UI (Playwright driving Debian's Chromium). Run scripts/setup.sh first.
#   scripts/test.sh              all tests
#   scripts/test.sh --sanitize   also the numerical core's suites (core, brdf, formats, gp, manifold) built
#                                with ASan/UBSan in build-sanitize/ (setup.sh --sanitize configures it)
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo"
[[ -x build/matlas ]] || { echo "test: build/matlas is missing: run scripts/setup.sh first" >&2; exit 1; }

jobs=$(nproc)
# Tests that use the installed environment maps and meshes find them here (setup.sh installs them).
[[ -d assets ]] && export MATLAS_ASSETS="$repo/assets"
cmake --build build -j "$jobs"
ctest --test-dir build --output-on-failure -j "$jobs"

if [[ "${1:-}" == "--sanitize" ]]; then
  suites=(core brdf formats gp manifold)
  targets=()
  for s in "${suites[@]}"; do targets+=("matlas_${s}_tests"); done
  cmake --build build-sanitize -j "$jobs" --target "${targets[@]}" | tail -n 2
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --test-dir build-sanitize --output-on-failure -j "$jobs" -L "^($(IFS='|'; echo "${suites[*]}"))\$"
fi

# Browser tests: Playwright (playwright-core) drives Debian's Chromium against `matlas demo`.
web/run-browser-tests.sh build/matlas
