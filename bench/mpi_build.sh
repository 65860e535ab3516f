#!/usr/bin/env bash
# Distributed build benchmark (issue 31): `matlas build` of a database in one process and with
# `mpirun -np P` (P = 2 by default), wall time, CPU and peak RSS per rank (/usr/bin/time), the
# raw read of all the files and of one rank's byte ranges (the per-rank read floor), in the same
# run, and the two models compared tensor by tensor (bench/compare_models.py).
#   bench/mpi_build.sh [DB] [P]   (default /tmp/map-db/merl24, 2)
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
db="${1:-/tmp/map-db/merl24}"
ranks="${2:-2}"
exe="$repo/build/matlas"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
files=("$db"/*.binary)
cat "${files[@]}" > /dev/null  # warm the page cache
now() { date +%s.%N; }

t0=$(now); cat "${files[@]}" > /dev/null; t1=$(now)
raw=$(echo "$t1 - $t0" | bc -l)
# One rank's byte ranges: the first 1/P of every file's values (MB-granular, as dd reads).
size=$(stat -L -c %s "${files[0]}")
share_mb=$((size / ranks / 1048576))
t0=$(now); for f in "${files[@]}"; do dd if="$f" bs=1M count="$share_mb" status=none of=/dev/null; done; t1=$(now)
raw_share=$(echo "$t1 - $t0" | bc -l)

/usr/bin/time -f "%e %M %U %S" -o "$out/time.single" "$exe" build "$db" -o "$out/single.matlas" --dim 5 --quiet > "$out/single.log"
mpirun -np "$ranks" --oversubscribe sh -c '/usr/bin/time -f "%e %M %U %S" -o "$0/time.rank$OMPI_COMM_WORLD_RANK" "$@"' \
  "$out" "$exe" build "$db" -o "$out/split.matlas" --dim 5 --quiet > "$out/split.log"
t0=$(now); mpirun -np "$ranks" --oversubscribe "$exe" build "$db" -o "$out/split2.matlas" --dim 5 --quiet > /dev/null; t1=$(now)
mpirun_wall=$(echo "$t1 - $t0" | bc -l)

echo "== single process"; grep -E "time |reading " "$out/single.log"
echo "== $ranks ranks (rank 0's report)"; grep -E "ranks |time |reading " "$out/split.log"
printf 'raw read of the inputs (cat, %d files):         %.2f s\n' "${#files[@]}" "$raw"
printf 'raw read of one rank'"'"'s share (dd, %d MB/file): %.2f s\n' "$share_mb" "$raw_share"
read -r wall rss user sys < "$out/time.single"
printf 'single: %.2f s wall, %.2f s user, %.2f s sys, peak RSS %.0f MB; wall / raw read %.2f\n' "$wall" "$user" "$sys" \
  "$(echo "$rss / 1024" | bc -l)" "$(echo "$wall / $raw" | bc -l)"
for r in $(seq 0 $((ranks - 1))); do
  read -r wall rss user sys < "$out/time.rank$r"
  printf 'rank %d: %.2f s wall, %.2f s user, %.2f s sys, peak RSS %.0f MB\n' "$r" "$wall" "$user" "$sys" \
    "$(echo "$rss / 1024" | bc -l)"
done
printf 'mpirun -np %d, whole job (launch included): %.2f s wall\n' "$ranks" "$mpirun_wall"
/usr/bin/python3 "$repo/bench/compare_models.py" "$out/single.matlas" "$out/split.matlas"
