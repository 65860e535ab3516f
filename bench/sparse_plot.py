#!/usr/bin/env python3
"""Error against the number of samples K from `matlas evaluate --sparse` (sparse.json): an SVG
plot (mean cube-root distance per method, with the nearest-material reference) and a Markdown
table. Standard library only.

    bench/sparse_plot.py REPORT/sparse.json -o docs/images/sparse-error.svg > table.md
"""
import argparse
import json

COLOURS = {"matlas-planned": "#d8333b", "matlas-random": "#f09a9e", "pca-condition": "#2f6fd0",
           "pca-random": "#9dbcf0"}
DASHES = {"matlas-planned": "", "matlas-random": "6,4", "pca-condition": "", "pca-random": "6,4"}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("report")
    ap.add_argument("-o", "--output", required=True)
    ap.add_argument("--title", default="")
    a = ap.parse_args()
    s = json.load(open(a.report))
    series = {}
    for r in s["results"]:
        series.setdefault(r["method"], []).append((r["count"], r["mean"], r["median"], r.get("ridge")))
    for v in series.values():
        v.sort()
    counts = sorted({c for v in series.values() for c, *_ in v})
    top = max([m for v in series.values() for _, m, _, _ in v] + [s["nearest_input"]]) * 1.1
    W, H, L, R, T, B = 640, 400, 60, 170, 30, 50
    x_of = {c: L + (W - L - R) * i / max(1, len(counts) - 1) for i, c in enumerate(counts)}
    y = lambda v: T + (H - T - B) * (1 - v / top)
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif" font-size="12">',
           f'<rect width="{W}" height="{H}" fill="white"/>']
    for k in range(6):
        v = top * k / 5
        out.append(f'<line x1="{L}" x2="{W - R}" y1="{y(v):.1f}" y2="{y(v):.1f}" stroke="#ddd"/>')
        out.append(f'<text x="{L - 6}" y="{y(v) + 4:.1f}" text-anchor="end">{v:.3f}</text>')
    for c in counts:
        out.append(f'<text x="{x_of[c]:.1f}" y="{H - B + 18}" text-anchor="middle">{c}</text>')
    out.append(f'<text x="{(L + W - R) / 2}" y="{H - 12}" text-anchor="middle">samples K (RGB each)</text>')
    out.append(f'<text x="14" y="{(T + H - B) / 2}" transform="rotate(-90 14 {(T + H - B) / 2})" '
               f'text-anchor="middle">cube-root distance (mean)</text>')
    ny = y(s["nearest_input"])
    out.append(f'<line x1="{L}" x2="{W - R}" y1="{ny:.1f}" y2="{ny:.1f}" stroke="#777" stroke-dasharray="2,3"/>')
    out.append(f'<text x="{W - R + 6}" y="{ny + 4:.1f}" fill="#555">nearest material</text>')
    for i, (method, v) in enumerate(sorted(series.items())):
        pts = " ".join(f"{x_of[c]:.1f},{y(m):.1f}" for c, m, _, _ in v)
        dash = f' stroke-dasharray="{DASHES.get(method, "")}"' if DASHES.get(method) else ""
        colour = COLOURS.get(method, "#000")
        out.append(f'<polyline points="{pts}" fill="none" stroke="{colour}" stroke-width="2"{dash}/>')
        for c, m, _, _ in v:
            out.append(f'<circle cx="{x_of[c]:.1f}" cy="{y(m):.1f}" r="3" fill="{colour}"/>')
        ly = T + 16 + 18 * i
        out.append(f'<line x1="{W - R + 6}" x2="{W - R + 30}" y1="{ly}" y2="{ly}" stroke="{colour}" stroke-width="2"{dash}/>')
        out.append(f'<text x="{W - R + 34}" y="{ly + 4}">{method}</text>')
    title = a.title or (f'{len(s["materials"])} materials left out in turn, maps of {s["inputs_per_map"]} inputs, '
                        f'q = {s["dim"]}')
    out.append(f'<text x="{L}" y="18">{title}</text>')
    out.append("</svg>")
    open(a.output, "w").write("\n".join(out) + "\n")
    print("| K | " + " | ".join(sorted(series)) + " |")
    print("|---:|" + "---:|" * len(series))
    for c in counts:
        cells = []
        for method in sorted(series):
            hit = [m for cc, m, _, _ in series[method] if cc == c]
            cells.append(f"{hit[0]:.4f}" if hit else "")
        print(f"| {c} | " + " | ".join(cells) + " |")
    rb = s["robustness"]
    print(f'\nnearest material {s["nearest_input"]:.4f}; robustness at K = {rb["count"]}: clean {rb["clean"]:.4f}, '
          f'corrupted {rb["corrupted"]:.4f} (robust), {rb["corrupted_least_squares"]:.4f} (least squares)')


if __name__ == "__main__":
    main()
