#!/usr/bin/env bash
# Installs the rendering assets (idempotent): the CC0 environment maps and meshes of the npm
# package @pmndrs/assets, decoded from their JS modules (`export default 'data:...;base64,...'`)
# into <repo>/assets/hdri/NAME.exr and <repo>/assets/models/NAME.glb (both git-ignored), and the
# Utah teapot generated from npm `three` into <repo>/assets/models/teapot.obj.
#
#   scripts/install-assets.sh [--force]
#
# Needs npm (registry access) the first time; afterwards it only decodes what is missing.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
version="1.7.0"
prefix="$repo/.cache/npm-assets"
package="$prefix/node_modules/@pmndrs/assets"
force=0
[[ "${1:-}" == "--force" ]] && force=1

hdris=(apartment bridge city dawn esplanade forest hall lab lobby night park sky studio sunrise
       sunset venice warehouse workshop)
models=(bunny suzi)

installed_version() {
  [[ -f "$package/package.json" ]] || return 1
  sed -n 's/.*"version": *"\([^"]*\)".*/\1/p' "$package/package.json" | head -n 1
}

if [[ "$(installed_version || true)" != "$version" ]]; then
  command -v npm > /dev/null || { echo "install-assets: npm is needed to fetch @pmndrs/assets" >&2; exit 1; }
  mkdir -p "$prefix"
  npm install --prefix "$prefix" --no-audit --no-fund --no-save "@pmndrs/assets@$version" >&2
fi

# decode SOURCE.js TARGET: strips `export default '<mime>;base64,` and the closing quote.
decode() {
  local source="$1" target="$2"
  if [[ -s "$target" && "$force" == 0 ]]; then return 0; fi
  [[ -f "$source" ]] || { echo "install-assets: missing $source" >&2; exit 1; }
  local tmp="$target.tmp-$$"
  sed -e "s/^export default '[^,]*,//" -e "s/'[;[:space:]]*\$//" "$source" | tr -d '\n' | base64 -d > "$tmp"
  [[ -s "$tmp" ]] || { rm -f "$tmp"; echo "install-assets: could not decode $source" >&2; exit 1; }
  mv "$tmp" "$target"
}

mkdir -p "$repo/assets/hdri" "$repo/assets/models"
for name in "${hdris[@]}"; do decode "$package/hdri/$name.exr.js" "$repo/assets/hdri/$name.exr"; done
for name in "${models[@]}"; do decode "$package/models/$name.glb.js" "$repo/assets/models/$name.glb"; done
# The Utah teapot for the path tracer's scenes (docs/GI.md): three.js's TeapotGeometry written as
# an OBJ by scripts/teapot-obj.mjs. Optional: skipped with a note when npm or node is missing.
three_version="0.187.0"
three_prefix="$repo/.cache/npm-three"
teapot="$repo/assets/models/teapot.obj"
if [[ ! -s "$teapot" || "$force" == 1 ]]; then
  if command -v npm > /dev/null && command -v node > /dev/null; then
    if [[ ! -f "$three_prefix/node_modules/three/package.json" ]] ||
       ! grep -q "\"version\": *\"$three_version\"" "$three_prefix/node_modules/three/package.json"; then
      mkdir -p "$three_prefix"
      npm install --prefix "$three_prefix" --no-audit --no-fund --no-save "three@$three_version" >&2
    fi
    node "$repo/scripts/teapot-obj.mjs" "$three_prefix/node_modules/three" "$teapot"
  else
    echo "install-assets: npm and node are needed for the teapot mesh; skipped" >&2
  fi
fi

echo "install-assets: ${#hdris[@]} environment maps and ${#models[@]} meshes in $repo/assets" >&2
