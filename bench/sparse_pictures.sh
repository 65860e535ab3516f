#!/usr/bin/env bash
# Reconstructions from sparse samples beside their measurements (docs/ACQUISITION.md): for each
# MATERIAL of the database DB, the map is built without it (q = 2), the plan's first K directions
# are "measured" on the left-out table (sample-plan --simulate) and fitted (fit-samples); the
# measured table and the fits are rendered on a sphere in the studio environment.
#   bench/sparse_pictures.sh DB OUTDIR "10 40" MATERIAL...   (MATLAS=path: another matlas binary)
# Writes OUTDIR/MATERIAL-measured.png, OUTDIR/MATERIAL-fit-K.png and the fit reports.
set -euo pipefail
db="$1" out="$2" counts="$3"
shift 3
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
matlas="${MATLAS:-$here/build/matlas}"
mkdir -p "$out"
render=(--width 256 --height 256 --spp 128 --seed 1)
for material in "$@"; do
  left="$out/$material-db"
  rm -rf "$left" && mkdir -p "$left"
  for f in "$db"/*.binary; do
    name="$(basename "$f" .binary)"
    [[ "$name" == "$material" ]] || ln -s "$(readlink -f "$f")" "$left/$name.binary"
  done
  table="$(readlink -f "$db/$material.binary")"
  "$matlas" build "$left" -o "$out/$material-map.matlas" --dim 2 --quiet
  "$matlas" render "$table" -o "$out/$material-measured.png" "${render[@]}"
  for k in $counts; do
    "$matlas" sample-plan "$out/$material-map.matlas" -k "$k" --simulate "$table" -o "$out/$material-plan-$k.csv" > /dev/null
    "$matlas" fit-samples "$out/$material-map.matlas" "$out/$material-plan-$k.csv" -o "$out/$material-fit-$k.binary" \
      --report "$out/$material-fit-$k.json"
    "$matlas" render "$out/$material-fit-$k.binary" -o "$out/$material-fit-$k.png" "${render[@]}"
  done
  rm -rf "$left" "$out/$material-map.matlas"
done
