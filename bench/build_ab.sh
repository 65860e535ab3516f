#!/usr/bin/env bash
# Whole `matlas build` runs of several binaries (for instance the commits before and after a
# change), alternating ROUNDS times so that they share the machine's noise, each round beginning
# with a raw read of the inputs (`cat`, the physical floor). Prints per run the load average, the
# wall/user/system times and the build's own "time" and "reading" lines (pass, latent placement,
# finishing; the pass's steps).
#   bench/build_ab.sh ROUNDS Q DB BINARY...      e.g. bench/build_ab.sh 2 2 /tmp/db83 old/matlas build/matlas
set -euo pipefail
rounds="$1"; q="$2"; db="$3"; shift 3
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
for ((r = 1; r <= rounds; ++r)); do
  start=$(date +%s.%N); cat "$db"/*.binary > /dev/null; end=$(date +%s.%N)
  echo "round $r: load $(cut -d' ' -f1 /proc/loadavg), raw cat of the inputs $(echo "$end - $start" | bc) s"
  for bin in "$@"; do
    load=$(cut -d' ' -f1 /proc/loadavg)
    /usr/bin/time -f "  $bin q=$q: wall %e s, user %U s, sys %S s (load $load)" "$bin" build "$db" -o "$out/m.matlas" \
      --dim "$q" --quiet 2>&1 | grep -E "wall|^  time |^  reading "
    rm -f "$out/m.matlas"
  done
done
