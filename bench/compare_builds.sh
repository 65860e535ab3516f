#!/usr/bin/env bash
# Compares `matlas build` binaries (for instance built from two commits) on the 100-material
# database, alternating them ROUNDS times so that both see the same noise, and prints for each
# the quietest (minimum) time of the pass and of its three steps, from the "reading" lines that
# `matlas build` prints.
#   bench/compare_builds.sh ROUNDS BINARY... [-- DB]   (DB default /tmp/matlas-bench-db)
# To build an older commit's binary: git worktree add /tmp/old COMMIT && cmake -S /tmp/old -B
# /tmp/old/build -G Ninja -DCMAKE_BUILD_TYPE=Release && cmake --build /tmp/old/build --target matlas
set -euo pipefail
rounds="$1"; shift
binaries=()
while (($#)) && [[ "$1" != "--" ]]; do binaries+=("$1"); shift; done
db=/tmp/matlas-bench-db
if (($#)); then shift; db="${1:-$db}"; fi
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
for ((r = 0; r < rounds; ++r)); do
  for i in "${!binaries[@]}"; do
    # "time  reading P s, ..." then "reading  files F s, centring and data S s, Gram and albedo G s"
    if ! "${binaries[$i]}" build "$db" -o "$out/m.matlas" --dim 5 > "$out/log" 2> "$out/err"; then
      cat "$out/err" >&2
      exit 1
    fi
    awk '/^  time /{p=$3} /^  reading /{print p, $3, $8, $13}' "$out/log" >> "$out/$i"
    rm -f "$out/m.matlas"
    sleep 1
  done
done
for i in "${!binaries[@]}"; do
  awk -v b="${binaries[$i]}" '{for (k = 1; k <= 4; ++k) if (NR == 1 || $k < m[k]) m[k] = $k}
    END {printf "%s: pass %.2f s, files %.2f s, centring and data %.2f s, Gram and albedo %.2f s (min of %d)\n",
         b, m[1], m[2], m[3], m[4], NR}' "$out/$i"
done
