#!/usr/bin/env bash
# The fit table of docs/EXPORT.md ("Analytic fits"): every MERL-grid table of the given folders
# fitted with the glTF metallic-roughness model (or, MODEL=principled-v1, Blender 2.8-3.6's
# Principled BSDF) by `matlas fit`, one markdown row per material:
#   material | base colour | metallic | roughness | specular | coat/roughness |
#   sheen/roughness (glTF) or sheen/tint (Principled v1) | cosine-weighted relative RMS % |
#   largest albedo difference % (0-75 deg) | cube-root distance | converged | seconds
# and a summary (median, quartiles) on stderr. The reports (.json) stay in $FIT_OUT if set.
# Usage: bench/fit_accuracy.sh [DIR...] (default /tmp/db83; MATLAS=build/matlas, MODEL=gltf)
set -euo pipefail
matlas=${MATLAS:-build/matlas}
model=${MODEL:-gltf}
dirs=("$@")
[ ${#dirs[@]} -eq 0 ] && dirs=(/tmp/db83)
out=${FIT_OUT:-$(mktemp -d)}
mkdir -p "$out"
for dir in "${dirs[@]}"; do
  for f in "$dir"/*.binary; do
    name=$(basename "$f" .binary)
    "$matlas" fit "$f" --model "$model" -o "$out/$name.json" > /dev/null
  done
done
/usr/bin/env python3 - "$out" <<'PY'
import json, pathlib, statistics, sys
rows = []
for p in sorted(pathlib.Path(sys.argv[1]).glob("*.json")):
    r = json.loads(p.read_text())
    rows.append((p.stem, r))
v1 = bool(rows) and rows[0][1].get("kind") == "principled-v1"
print(f"| material | base colour | metallic | roughness | specular | coat / roughness | sheen / {'tint' if v1 else 'roughness'} | RMS % | albedo % | cbrt | conv. | s |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|")
for name, r in rows:
    m, e, f = r["parameters"], r["error"], r["fit"]
    base = " ".join(f"{c:.3f}" for c in m["base_color"])
    coat = f"{m['coat']:.2f} / {m['coat_roughness']:.2f}" if v1 else f"{m['clearcoat']:.2f} / {m['clearcoat_roughness']:.2f}"
    sheen = f"{m['sheen']:.2f} / {m['sheen_tint']:.2f}" if v1 else f"{max(m['sheen_color']):.2f} / {m['sheen_roughness']:.2f}"
    print(f"| {name} | {base} | {m['metallic']:.2f} | {m['roughness']:.3f} | {m['specular']:.2f} | "
          f"{coat} | {sheen} | {100 * e['relative_rms']:.1f} | "
          f"{100 * e['albedo_error']:.1f} | {e['cbrt_distance']:.4f} | {'yes' if f['converged'] else 'no'} | "
          f"{f['seconds']:.1f} |")
def q(values, f):
    s = sorted(values); return s[min(len(s) - 1, int(f * len(s)))]
for key, label in (("relative_rms", "RMS %"), ("albedo_error", "albedo %")):
    v = [100 * r["error"][key] for _, r in rows]
    print(f"{label}: median {statistics.median(v):.1f}, quartiles {q(v, .25):.1f}-{q(v, .75):.1f}, "
          f"p90 {q(v, .9):.1f}, max {max(v):.1f}; under 5: {sum(x < 5 for x in v)}, under 10: "
          f"{sum(x < 10 for x in v)}, under 20: {sum(x < 20 for x in v)} of {len(v)}", file=sys.stderr)
t = [r["fit"]["seconds"] for _, r in rows]
print(f"seconds per fit: median {statistics.median(t):.1f}, max {max(t):.1f}; not converged: "
      f"{sum(not r['fit']['converged'] for _, r in rows)}", file=sys.stderr)
PY
