#!/usr/bin/env bash
# The requests of one drag step at once (weights, slice, lobe, albedo: what the browser asks for a
# new point besides the preview) against a running `matlas serve`, wall time per burst: the four
# for one point ("same"), and for four points 1e-6 apart ("distinct": each request solves its own
# weights, as every request did before the server kept the latest points' weights), alternated.
#   bench/drag_burst.sh [URL] [RUNS] [Q]   (default http://127.0.0.1:8080, 6 runs, q = 5)
set -euo pipefail
url="${1:-http://127.0.0.1:8080}"
runs="${2:-6}"
q="${3:-5}"
now() { date +%s.%N; }
point() {  # point R E: run R's point (coordinates drawn in [-0.5, 0.5], seed R), the last one offset by E
  awk -v seed="$1" -v q="$q" -v e="$2" 'BEGIN { srand(seed); s = "";
    for (k = 0; k < q; ++k) s = s (k ? "," : "") sprintf("%.9f", rand() - 0.5 + (k == q - 1 ? e : 0)); print s }'
}
burst() {  # burst X1 X2 X3 X4: the four requests at once, prints the seconds
  local t0 t1
  t0=$(now)
  curl -s -o /dev/null -X POST "$url/api/weights" -d "{\"x\": [$1], \"top\": 8}" &
  curl -s -o /dev/null -X POST "$url/api/slice" -d "{\"x\": [$2], \"phi_d\": 90}" &
  curl -s -o /dev/null -X POST "$url/api/lobe" -d "{\"x\": [$3], \"theta_i\": 30, \"samples\": 181}" &
  curl -s -o /dev/null -X POST "$url/api/albedo" -d "{\"x\": [$4]}" &
  wait
  t1=$(now)
  echo "$t1 - $t0" | bc -l
}
for ((r = 1; r <= runs; ++r)); do
  d=$(burst "$(point $r 0)" "$(point $r 1e-6)" "$(point $r 2e-6)" "$(point $r 3e-6)")
  s=$(burst "$(point $((r + 100)) 0)" "$(point $((r + 100)) 0)" "$(point $((r + 100)) 0)" "$(point $((r + 100)) 0)")
  printf 'run %d: distinct points %.3f s, one point %.3f s\n' "$r" "$d" "$s"
done
