#!/usr/bin/env bash
# Makes the 100-material benchmark database: the 24 realistic MERL-like materials of
# ../shared (tabulated from their neural fits) plus 76 synthetic ones (`matlas synth`).
#   bench/make_bench_db.sh [DIR]   (default /tmp/matlas-bench-db; about 3.5 GB)
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
dir="${1:-/tmp/matlas-bench-db}"
shared="$repo/../shared"
mkdir -p "$dir"
if [[ $(ls "$dir"/*.binary 2>/dev/null | wc -l) -ge 100 ]]; then
  echo "$dir already holds the benchmark database" >&2
  exit 0
fi
dpkg-query -W python3-h5py python3-numpy > /dev/null 2>&1 ||
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq python3-numpy python3-h5py
/usr/bin/python3 "$shared/tools/nbrdf2merl.py" "$dir" "$shared"/data/nbrdf-merl/*.h5 > /dev/null
"$repo/build/matlas" synth -o "$dir/synthetic" --count 76 --seed 7 > /dev/null
mv "$dir"/synthetic/*.binary "$dir"/ && rmdir "$dir/synthetic"
ls "$dir"/*.binary | wc -l
