#!/usr/bin/env bash
# The preview of a material before and after refinement at rest, as the browser shows them:
# POST /api/preview (the basis image), then POST /api/preview/refine for about SECONDS of calls.
#   bench/refine_snapshot.sh URL MODEL MATERIAL SECONDS OUTDIR
# Writes OUTDIR/MATERIAL-basis.png and OUTDIR/MATERIAL-refined.png and prints the refinement's
# samples and estimated error. Needs `matlas serve MODEL` running at URL.
set -euo pipefail
url="${1%/}" model="$2" material="$3" seconds="$4" out="$5"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
x=$("$here/build/matlas" latent "$model" | awk -v m="$material" '$1 == m { printf "%s", $2; for (i = 3; i <= NF; i++) printf ",%s", $i }')
[[ -n "$x" ]] || { echo "refine_snapshot: no material $material in $model" >&2; exit 1; }
mkdir -p "$out"
curl -sf -X POST -d "{\"x\":[$x]}" "$url/api/preview" -o "$out/$material-basis.png"
end=$((SECONDS + seconds))
while ((SECONDS < end)); do
  curl -sf -D "$out/.headers" -X POST -d "{\"x\":[$x],\"seconds\":1}" "$url/api/preview/refine" -o "$out/$material-refined.png"
  grep -qi "x-matlas-converged: 1" "$out/.headers" && break
done
grep -i "x-matlas-\(spp\|error\|seconds\)" "$out/.headers" | tr -d '\r'
rm -f "$out/.headers"
