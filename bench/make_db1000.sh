#!/usr/bin/env bash
# Makes the 1000-material database of bench/e2e_1000.sh (issue 31, item 1), about 35 GB:
#   - the 83 realistic materials of ../shared (MERL, RGL and Nielsen neural fits, tabulated by
#     ../shared/tools/nbrdf2merl.py; linked from REALISTIC when it already holds them),
#   - 417 analytic materials, `matlas synth --count 417 --seed 1000` (GGX conductors and plastics,
#     Lambertian paints, Blinn-Phong: roughness and colours drawn as docs/ANALYTIC.md says),
#   - 500 random convex mixtures of 2 or 3 realistic ones (bench/mix_materials.py, seed 1000):
#     linear in the physical BRDF values, weights uniform on the simplex.
# Deterministic: the same seeds give the same files. Resumable: files already there are kept.
#   bench/make_db1000.sh [DIR]   (default /tmp/matlas-db1000; REALISTIC=/tmp/db83; MATLAS_BUILD=build)
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
dir="${1:-/tmp/matlas-db1000}"
realistic="${REALISTIC:-/tmp/db83}"
build="${MATLAS_BUILD:-$repo/build}"
shared="$repo/../shared"
[[ -d "$shared" ]] || shared=/work/shared
count() { find "$1" -maxdepth 1 -name '*.binary' 2>/dev/null | wc -l; }

if [[ $(count "$realistic") -lt 83 ]]; then
  dpkg-query -W python3-h5py python3-numpy > /dev/null 2>&1 ||
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq python3-numpy python3-h5py
  mkdir -p "$realistic"
  for set in nbrdf-merl nbrdf-rgl nbrdf-nielsen; do
    todo=()
    for h5 in "$shared/data/$set"/*.h5; do
      [[ -e "$realistic/$(basename "${h5%.h5}").binary" ]] || todo+=("$h5")
    done
    [[ ${#todo[@]} -eq 0 ]] || /usr/bin/python3 "$shared/tools/nbrdf2merl.py" "$realistic" "${todo[@]}" > /dev/null
  done
fi
[[ $(count "$realistic") -eq 83 ]] || { echo "$realistic: expected the 83 realistic materials" >&2; exit 1; }

mkdir -p "$dir"
for f in "$realistic"/*.binary; do
  [[ -e "$dir/$(basename "$f")" ]] || ln -s "$(readlink -f "$f")" "$dir/$(basename "$f")"
done
if [[ $(find "$dir" -maxdepth 1 -name '*.binary' ! -name 'mix-*' | wc -l) -lt 500 ]]; then
  nice "$build/matlas" synth -o "$dir/synthetic" --count 417 --seed 1000 > /dev/null
  mv "$dir"/synthetic/*.binary "$dir"/ && rmdir "$dir/synthetic"
fi
PYTHONPATH="$build/python" nice /usr/bin/python3 "$repo/bench/mix_materials.py" --count 500 --seed 1000 \
  -o "$dir" "$realistic"/*.binary
n=$(count "$dir")
[[ $n -eq 1000 ]] || { echo "$dir holds $n materials, expected 1000" >&2; exit 1; }
echo "$dir: $n materials"
