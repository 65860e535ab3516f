#!/usr/bin/env bash
# Runs every test: the GoogleTest suites (ctest) on the Release build, then the browser tests of
# the web UI (Playwright driving Debian's Chromium). Run scripts/setup.sh first.
#   scripts/test.sh              all tests
#   scripts/test.sh --sanitize   also the suites built with ASan/UBSan (setup.sh --sanitize)
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo"
[[ -x build/matlas ]] || { echo "test: build/matlas is missing: run scripts/setup.sh first" >&2; exit 1; }

jobs=$(nproc)
cmake --build build -j "$jobs"
ctest --test-dir build --output-on-failure -j "$jobs"

if [[ "${1:-}" == "--sanitize" ]]; then
  cmake --build build-sanitize -j "$jobs"
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --test-dir build-sanitize --output-on-failure -j "$jobs"
fi

# Browser tests: Playwright (playwright-core) drives Debian's Chromium against `matlas demo`.
web/run-browser-tests.sh build/matlas
