#!/usr/bin/env bash
# Tables beside their RGL .bsdf exports (docs/EXPORT.md, "Accuracy"): for each table file,
# `matlas export` writes the .bsdf with fitted samples and with point samples
# (--fit-iterations 0); each file is read back as a renderer would evaluate it and resampled onto
# the MERL grid (`matlas import`), and the table and both files are rendered on a sphere in the
# studio environment with the same samples. One picture per table: the table, the fitted file, and
# |file - table| x GAIN (the tone-mapped pixels) for the fitted and the point-sampled file.
#   bench/export_bsdf_pictures.sh OUTDIR TABLE.binary...   (MATLAS=path: another matlas binary;
#   GAIN=8, SPP=256)
# Writes OUTDIR/export-NAME.png.
set -euo pipefail
out="$1"
mkdir -p "$out"
shift
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
matlas="${MATLAS:-$here/build/matlas}"
gain="${GAIN:-8}"
render=(--width 192 --height 192 --spp "${SPP:-256}" --seed 1)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/fitted" "$tmp/points"
for table in "$@"; do
  name="$(basename "$table" .binary)"
  "$matlas" export "$table" -o "$tmp/fitted/$name.bsdf" --no-check > /dev/null
  "$matlas" export "$table" -o "$tmp/points/$name.bsdf" --no-check --fit-iterations 0 > /dev/null
  for kind in fitted points; do
    "$matlas" import "$tmp/$kind/$name.bsdf" -o "$tmp/$kind-merl" > /dev/null
    "$matlas" render "$tmp/$kind-merl/$name.binary" -o "$tmp/$kind.png" "${render[@]}" > /dev/null
    convert "$tmp/$kind.png" ppm:- > "$tmp/$kind.ppm"
  done
  "$matlas" render "$table" -o "$tmp/table.png" "${render[@]}" > /dev/null
  convert "$tmp/table.png" ppm:- > "$tmp/table.ppm"
  "$here/bench/join_images.py" "$tmp/table.ppm" "$tmp/fitted.ppm" "diff:$tmp/fitted.ppm:$tmp/table.ppm:$gain" \
    "diff:$tmp/points.ppm:$tmp/table.ppm:$gain" -o "$out/export-$name.png"
  echo "$out/export-$name.png"
done
