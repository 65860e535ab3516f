#!/usr/bin/env bash
# The accuracy table of docs/EXPORT.md: every MERL-grid table of the given folders exported as an
# RGL .bsdf file by `matlas export --format bsdf`, read back by matlas' own reader, and compared
# with the table (the export's own check). One markdown row per material:
#   material | size MB | cosine-weighted relative RMS % at the bin centres | the same between them
#   (one uniform point per bin, against the table's smooth lookup) | largest albedo difference %
#   (0-75 deg) | variance of the MC luminance albedo at 30 deg, own sampling vs cosine sampling |
#   with BASELINE=1: the RMS at and between the centres of the samples taken at the nodes
#   (--fit-iterations 0), the samples not fitted
# Usage: bench/export_bsdf_accuracy.sh [matlas] DIR... (default: build/matlas /tmp/map-db/{merl24,rgl51,nielsen8})
set -euo pipefail
matlas=${MATLAS:-build/matlas}
dirs=("$@")
[ ${#dirs[@]} -eq 0 ] && dirs=(/tmp/map-db/merl24 /tmp/map-db/rgl51 /tmp/map-db/nielsen8)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
baseline=${BASELINE:-0}
if [ "$baseline" = 1 ]; then
  echo "| material | MB | RMS % | between % | albedo % | var own 30 | var cosine 30 | not fitted: RMS % | between % |"
  echo "|---|---|---|---|---|---|---|---|---|"
else
  echo "| material | MB | RMS % | between % | albedo % | var own 30 | var cosine 30 |"
  echo "|---|---|---|---|---|---|---|"
fi
for dir in "${dirs[@]}"; do
  for f in "$dir"/*.binary; do
    name=$(basename "$f" .binary)
    log=$("$matlas" export "$f" -o "$out/$name.bsdf")
    mb=$(sed -n 's/.*, \([0-9.]*\) MB).*/\1/p' <<<"$log")
    rms=$(sed -n 's/.*fidelity.*relative RMS \([0-9.]*\) %.*/\1/p' <<<"$log")
    between=$(sed -n 's/.*fidelity.*, \([0-9.]*\) % between.*/\1/p' <<<"$log")
    alb=$(sed -n 's/.*largest albedo difference \([0-9.]*\) %.*/\1/p' <<<"$log")
    own=$(sed -n 's/.*albedo 30 deg.*variance \([0-9.e+-]*\) (own) vs \([0-9.e+-]*\) (cosine).*/\1/p' <<<"$log")
    cos=$(sed -n 's/.*albedo 30 deg.*variance \([0-9.e+-]*\) (own) vs \([0-9.e+-]*\) (cosine).*/\2/p' <<<"$log")
    if [ "$baseline" = 1 ]; then
      plain=$("$matlas" export "$f" -o "$out/$name.bsdf" --fit-iterations 0 | grep fidelity)
      prms=$(sed -n 's/.*relative RMS \([0-9.]*\) %.*/\1/p' <<<"$plain")
      pbetween=$(sed -n 's/.*, \([0-9.]*\) % between.*/\1/p' <<<"$plain")
      echo "| $name | $mb | $rms | $between | $alb | $own | $cos | $prms | $pbetween |"
    else
      echo "| $name | $mb | $rms | $between | $alb | $own | $cos |"
    fi
    rm -f "$out/$name.bsdf"
  done
done
