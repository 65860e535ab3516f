#!/usr/bin/env bash
# Tables beside their glTF metallic-roughness fits (docs/EXPORT.md, "Analytic fits"): for each
# table file, `matlas fit` tabulates the fit (-o X.binary), both are rendered on a sphere in the
# studio environment with the same samples, and the two are put side by side (table left, fit
# right; decoded with `convert FILE.png ppm:-`, joined by bench/join_images.py).
#   bench/fit_pictures.sh OUTDIR TABLE.binary...   (MATLAS=path: another matlas binary)
# Writes OUTDIR/fit-NAME.png and the fit reports OUTDIR/NAME.json.
set -euo pipefail
out="$1"
shift
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
matlas="${MATLAS:-$here/build/matlas}"
mkdir -p "$out"
render=(--width 192 --height 192 --spp 64 --seed 1)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for table in "$@"; do
  name="$(basename "$table" .binary)"
  "$matlas" fit "$table" -o "$tmp/$name-fit.binary" -o "$out/$name.json" > /dev/null
  "$matlas" render "$table" -o "$tmp/$name-table.png" "${render[@]}" > /dev/null
  "$matlas" render "$tmp/$name-fit.binary" -o "$tmp/$name-fit.png" "${render[@]}" > /dev/null
  convert "$tmp/$name-table.png" ppm:- > "$tmp/a.ppm"
  convert "$tmp/$name-fit.png" ppm:- > "$tmp/b.ppm"
  "$here/bench/join_images.py" "$tmp/a.ppm" "$tmp/b.ppm" -o "$out/fit-$name.png"
done
