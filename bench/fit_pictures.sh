#!/usr/bin/env bash
# Tables beside their glTF metallic-roughness fits (docs/EXPORT.md, "Analytic fits"): for each
# table file, `matlas fit` tabulates the fit (-o X.binary), both are rendered on a sphere in the
# studio environment with the same samples, and the two are put side by side (table left, fit
# right; decoded with `convert FILE.png ppm:-`, joined and written as PNG by a few lines of Python).
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
  /usr/bin/env python3 - "$tmp/a.ppm" "$tmp/b.ppm" "$out/fit-$name.png" <<'PY'
import struct, sys, zlib
def read_ppm(path):
    data = open(path, "rb").read()
    fields, pos = [], 0
    while len(fields) < 4:  # P6 width height maxval, separated by whitespace
        while data[pos:pos + 1].isspace(): pos += 1
        end = pos
        while not data[end:end + 1].isspace(): end += 1
        fields.append(data[pos:end]); pos = end
    w, h = int(fields[1]), int(fields[2])
    return w, h, data[pos + 1:pos + 1 + 3 * w * h]
(wa, ha, a), (wb, hb, b) = read_ppm(sys.argv[1]), read_ppm(sys.argv[2])
assert ha == hb
rows = b"".join(b"\0" + a[3 * wa * y:3 * wa * (y + 1)] + b[3 * wb * y:3 * wb * (y + 1)] for y in range(ha))
def chunk(kind, body):
    return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", wa + wb, ha, 8, 2, 0, 0, 0)) + \
      chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b"")
open(sys.argv[3], "wb").write(png)
PY
done
