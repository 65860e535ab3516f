#!/usr/bin/env bash
# End-to-end build benchmark: `matlas build` of the 100-material database (n = 100, q = 5), its
# wall time and peak RSS, next to reading the same files raw (cat) in the same run.
#   bench/e2e_build.sh [DB]   (default /tmp/matlas-bench-db, made by bench/make_bench_db.sh)
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
db="${1:-/tmp/matlas-bench-db}"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
cat "$db"/*.binary > /dev/null  # warm the page cache
sync; sleep 10  # let the disk finish discarding the files of an earlier run (mounted with discard)
t0=$(date +%s.%N); cat "$db"/*.binary > /dev/null; t1=$(date +%s.%N)
raw=$(echo "$t1 - $t0" | bc -l)
/usr/bin/time -f "%e %M" -o "$out/time" "$repo/build/matlas" build "$db" -o "$out/m.matlas" --dim 5 --quiet > "$out/log"
read -r wall rss_kb < "$out/time"
cat "$out/log"
printf 'raw read of the inputs (cat): %.2f s\n' "$raw"
printf 'matlas build, n=%d q=5:      %.2f s wall, peak RSS %.0f MB\n' "$(ls "$db"/*.binary | wc -l)" "$wall" "$(echo "$rss_kb / 1024" | bc -l)"
printf 'build / raw read:             %.2f\n' "$(echo "$wall / $raw" | bc -l)"
