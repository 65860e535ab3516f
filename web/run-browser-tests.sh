#!/usr/bin/env bash
# Browser tests of the web UI: builds web/dist, then drives Debian's Chromium (headless, through
# playwright-core; no browser download) against `matlas demo` on a small synthetic database.
#
#   web/run-browser-tests.sh [PATH/TO/matlas]      (default: build/matlas)
#
# Needs node >= 20 and /usr/bin/chromium (or $CHROMIUM). Prints node's test summary; exit status
# non-zero on failure. Runs every test file of web/tests (the page, scene switching, and the API
# schema against web/src/api.ts, docs/API.md and the live server); screenshots are left in
# web/test-results/.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
bin="$(realpath "${1:-$here/../build/matlas}")"
[[ -x "$bin" ]] || { echo "run-browser-tests: no matlas binary at $bin (build it first)" >&2; exit 1; }
cd "$here"
[[ -d node_modules/playwright-core && -d node_modules/vite ]] || npm ci --no-audit --no-fund
npm run --silent build
MATLAS_BIN="$bin" node --test --test-concurrency=1 tests/
