#!/usr/bin/env bash
# Sets up matlas on a fresh Debian machine (idempotent): installs the Debian packages it needs,
# builds the C++ code in Release, installs the rendering assets (npm package @pmndrs/assets) and
# builds the web UI. Usage: scripts/setup.sh [--sanitize]  (also configures build-sanitize/).
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo"

packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libcli11-dev nlohmann-json3-dev libcpp-httplib-dev libopenblas-dev libxxhash-dev
  liblbfgspp-dev libtinyexr-dev libopenexr-dev libdraco-dev libstb-dev libembree-dev libtbb-dev
  libtinygltf-dev libpugixml-dev
  libgtest-dev libbenchmark-dev
  libopenmpi-dev openmpi-bin
  python3-dev python3-pybind11 python3-numpy python3-pytest python3-setuptools python3-pip
  clang-14 libclang-rt-14-dev
  nodejs npm chromium fonts-dejavu-core libjs-chart.js
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# A machine may have node and npm from elsewhere (not from Debian): keep those.
if command -v node > /dev/null && command -v npm > /dev/null; then
  missing=("${missing[@]/nodejs}")
  missing=("${missing[@]/npm}")
fi
read -r -a missing <<< "${missing[*]}"
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}" >&2
  sudo_cmd=()
  [[ $(id -u) -eq 0 ]] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

jobs=$(nproc)
# MATLAS_CMAKE_ARGS adds CMake options to every build folder (CI: -DMATLAS_BUILD_BENCH=OFF, the
# benchmarks are not run there, and -DCMAKE_UNITY_BUILD=ON, half the compile time).
# shellcheck disable=SC2086
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release ${MATLAS_CMAKE_ARGS:-} > /dev/null
cmake --build build -j "$jobs"
if [[ "${1:-}" == "--sanitize" ]]; then
  # Configured here; scripts/test.sh --sanitize builds and runs the core suites in it.
  cmake -S . -B build-sanitize -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMATLAS_SANITIZE=ON \
        -DMATLAS_BUILD_BENCH=OFF -DMATLAS_PYTHON=OFF ${MATLAS_CMAKE_ARGS:-} > /dev/null
fi

[[ -x scripts/install-assets.sh ]] && scripts/install-assets.sh
if [[ -f web/package.json ]]; then
  (cd web && npm ci --no-audit --no-fund --loglevel=error && npm run build --silent)
fi
echo "setup: done; the matlas command is build/matlas" >&2
