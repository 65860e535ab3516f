#!/usr/bin/env bash
# A real client check of `matlas fit` (docs/EXPORT.md, "Blender"): Blender (Debian's, `blender -b`,
# Cycles on the CPU) renders the fitted Principled BSDF, built by the fit's own Blender script
# (`matlas fit -o X.py`), on a sphere under the environment map, camera and resolution of
# `matlas render` of the fit itself (its report, `matlas fit -o X.json`: the analytic model, not a
# table of it); each side renders twice with two seeds, and bench/blender_check.py compares the
# mean radiance over the pixels wholly on the sphere with the Monte Carlo noise of the two means
# (z = difference / standard error).
# First a Lambertian sphere (Blender's Diffuse BSDF against a tabulated Lambert BRDF), which checks
# the conventions: camera, map orientation, units.
#   bench/blender_check.sh OUTDIR TABLE.binary...
#   (MATLAS=path, BLENDER=path, ENV=studio, SIZE=192, SPP=256; LAMBERT=0 skips the convention check;
#    MODEL=principled-v1 fits Blender 2.8-3.6's own Principled BSDF instead of the glTF model;
#    BLUR=R renders under the map box-blurred over 2R x 2R texels; both sides get the map as matlas
#    reads it, its negative texels 0)
# Writes OUTDIR/NAME.json (the comparison), OUTDIR/NAME-fit.json (the fit's report) and prints a
# summary line per material. Not run in CI (needs Blender; about a minute per render).
set -euo pipefail
out="$1"
shift
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
matlas="${MATLAS:-$here/build/matlas}"
blender="${BLENDER:-blender}"
env="${ENV:-studio}"
size="${SIZE:-192}"
spp="${SPP:-256}"
model="${MODEL:-gltf}"
assets="${MATLAS_ASSETS:-$here/assets}"
map="$assets/hdri/$env.exr"
[[ -f "$map" ]] || { echo "blender_check: no environment map $map (set MATLAS_ASSETS)" >&2; exit 1; }
export MATLAS_ASSETS="$assets"
mkdir -p "$out"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
py="$here/bench/blender_check.py"
run_blender() { "$blender" -b --factory-startup --python "$py" -- "$@" > "$tmp/blender.log" 2>&1 ||
  { tail -20 "$tmp/blender.log" >&2; exit 1; }; }
# Both sides render the map as matlas reads it (render/environment.h: negative texels, the ringing
# of a processed map around its lights, are 0; Cycles would render them as negative light), or
# blurred (BLUR=R).
read_as="$tmp/$env${BLUR:+-blur$BLUR}.exr"
run_blender blur --env "$map" --out "$read_as" --radius "${BLUR:-0}"
map="$read_as"
env="$map"

# check NAME MATERIAL (--snippet FIT.py | --diffuse R,G,B); MATERIAL: a table or a fit report
check() {
  local name="$1" material="$2"
  shift 2
  for seed in 1 2; do
    "$matlas" render "$material" -o "$tmp/$name-m$seed.exr" --env "$env" --width "$size" --height "$size" --spp "$spp" \
      --seed "$seed" > /dev/null
    local start=$SECONDS
    run_blender render --out "$tmp/$name-b$seed.exr" --env "$map" --size "$size" --spp "$spp" --seed "$seed" "$@"
    echo "  $name: Blender render (seed $seed) $((SECONDS - start)) s" >&2
  done
  run_blender compare --blender "$tmp/$name-b1.exr" "$tmp/$name-b2.exr" --matlas "$tmp/$name-m1.exr" \
    "$tmp/$name-m2.exr" --json "$out/$name.json"
  python3 - "$name" "$out/$name.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[2]))
f = lambda key: " ".join(f"{100 * v:+.2f}" for v in r[key])
print(f"{sys.argv[1]:28s} mean difference {f('mean_difference_relative')} %  (standard error "
      f"{' '.join(f'{100 * v:.2f}' for v in r['standard_error_relative'])} %, z {' '.join(f'{v:+.1f}' for v in r['z'])}); "
      f"pixel RMS {' '.join(f'{100 * v:.1f}' for v in r['pixel_rms_relative'])} % vs noise "
      f"{' '.join(f'{100 * v:.1f}' for v in r['pixel_noise_rms_relative'])} %")
PY
}

# A Lambertian table of albedo 0.5 (MERL's stored units: f / channel scale).
python3 - "$tmp/lambert.binary" <<'PY'
import array, math, struct, sys
n = 90 * 90 * 180
with open(sys.argv[1], "wb") as f:
    f.write(struct.pack("<3i", 90, 90, 180))
    for scale in (1 / 1500, 1.15 / 1500, 1.66 / 1500):
        f.write((array.array("d", [0.5 / math.pi / scale]) * n).tobytes())
PY
echo "blender_check: $("$blender" --version 2>/dev/null | head -1), $(basename "$env"), ${size}x${size}, $spp spp, model $model, $(date -u +%F)" >&2
[[ "${LAMBERT:-1}" == 0 ]] || check lambert "$tmp/lambert.binary" --diffuse 0.5,0.5,0.5

for table in "$@"; do
  name="$(basename "$table" .binary)"
  "$matlas" fit "$table" --model "$model" -o "$tmp/$name.py" -o "$out/$name-fit.json" > /dev/null
  check "$name" "$out/$name-fit.json" --snippet "$tmp/$name.py"
done
