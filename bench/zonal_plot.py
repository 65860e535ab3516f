#!/usr/bin/env python3
"""Summarise bench_zonal_accuracy CSVs (docs/REALTIME.md): per-class error against L as an SVG
plot and Markdown tables. Standard library only.

    bench/zonal_plot.py -o docs/realtime-convergence.svg forest.csv city.csv studio.csv > summary.md

Classes by gloss = ln(pi f_peak / A) (see bench_zonal_accuracy.cpp): diffuse < 1 <= glossy < 6
<= mirror-like. The plotted error is the noise-free relative RMS error (rms column); the tables
also give l1 (which includes the reference's noise) and the noise itself.
"""
import argparse
import csv
import math
import os
from collections import defaultdict

CLASSES = ["diffuse", "glossy", "mirror-like"]
COLOURS = {"diffuse": "#3b7dd8", "glossy": "#d8833b", "mirror-like": "#555555"}
DASHES = ["", "6,4", "2,3"]


def klass(gloss):
    return "diffuse" if gloss < 1.0 else ("glossy" if gloss < 6.0 else "mirror-like")


def load(path):
    rows = list(csv.DictReader(open(path)))
    env = os.path.splitext(os.path.basename(path))[0]
    data = defaultdict(dict)  # material -> L -> row
    for r in rows:
        data[r["material"]][int(r["L"])] = {k: float(r[k]) for k in ("gloss", "l1", "rms", "noise")}
    return env, data


def mean(xs):
    return sum(xs) / len(xs) if xs else float("nan")


def svg(series, bands, out):
    w, h, left, right, top, bottom = 640, 400, 70, 170, 20, 50
    lo, hi = 1e-3, 3.0
    def x(L):
        return left + (L - bands[0]) / (bands[-1] - bands[0]) * (w - left - right)
    def y(v):
        v = min(max(v, lo), hi)
        return top + (math.log10(hi) - math.log10(v)) / (math.log10(hi) - math.log10(lo)) * (h - top - bottom)
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" font-family="sans-serif" font-size="12">',
             f'<rect width="{w}" height="{h}" fill="white"/>']
    for e in range(-3, 1):
        for m in (1, 2, 5):
            v = m * 10 ** e
            if lo <= v <= hi:
                parts.append(f'<line x1="{left}" x2="{w - right}" y1="{y(v):.1f}" y2="{y(v):.1f}" stroke="#ddd"/>')
                parts.append(f'<text x="{left - 6}" y="{y(v) + 4:.1f}" text-anchor="end">{v * 100:g} %</text>')
    for L in bands:
        parts.append(f'<line x1="{x(L):.1f}" x2="{x(L):.1f}" y1="{top}" y2="{h - bottom}" stroke="#eee"/>')
        parts.append(f'<text x="{x(L):.1f}" y="{h - bottom + 16}" text-anchor="middle">{L}</text>')
    parts.append(f'<line x1="{left}" x2="{w - right}" y1="{y(0.05):.1f}" y2="{y(0.05):.1f}" stroke="#c00" stroke-dasharray="3,3"/>')
    parts.append(f'<text x="{w - right - 4}" y="{y(0.05) - 4:.1f}" text-anchor="end" fill="#c00">5 % target</text>')
    parts.append(f'<text x="{(left + w - right) / 2}" y="{h - 12}" text-anchor="middle">highest band L</text>')
    parts.append(f'<text x="16" y="{(top + h - bottom) / 2}" transform="rotate(-90 16 {(top + h - bottom) / 2})" '
                 'text-anchor="middle">mean relative RMS error (noise-free)</text>')
    legend_y = top + 10
    for (env, cls, dash), values in series.items():
        pts = " ".join(f"{x(L):.1f},{y(v):.1f}" for L, v in values)
        parts.append(f'<polyline points="{pts}" fill="none" stroke="{COLOURS[cls]}" stroke-width="2" '
                     f'stroke-dasharray="{dash}"/>')
        for L, v in values:
            parts.append(f'<circle cx="{x(L):.1f}" cy="{y(v):.1f}" r="2.5" fill="{COLOURS[cls]}"/>')
        parts.append(f'<line x1="{w - right + 10}" x2="{w - right + 34}" y1="{legend_y}" y2="{legend_y}" '
                     f'stroke="{COLOURS[cls]}" stroke-width="2" stroke-dasharray="{dash}"/>')
        parts.append(f'<text x="{w - right + 40}" y="{legend_y + 4}">{cls}, {env}</text>')
        legend_y += 18
    parts.append("</svg>")
    open(out, "w").write("\n".join(parts) + "\n")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("-o", "--output", required=True)
    ap.add_argument("csv", nargs="+")
    args = ap.parse_args()
    series = {}
    bands = None
    for i, path in enumerate(args.csv):
        env, data = load(path)
        bands = sorted({L for m in data.values() for L in m})
        by_class = defaultdict(list)
        for name, per_l in data.items():
            by_class[klass(next(iter(per_l.values()))["gloss"])].append(name)
        print(f"\n### {env}\n")
        print("| class | materials | " + " | ".join(f"L={L} rms / l1" for L in bands) + " | noise (l1) |")
        print("|---|---|" + "---|" * (len(bands) + 1))
        for cls in CLASSES:
            names = by_class.get(cls, [])
            if not names:
                continue
            cells = []
            values = []
            for L in bands:
                rms = mean([data[n][L]["rms"] for n in names])
                l1 = mean([data[n][L]["l1"] for n in names])
                cells.append(f"{rms * 100:.1f} % / {l1 * 100:.1f} %")
                values.append((L, rms))
            noise = mean([data[n][bands[0]]["noise"] for n in names])
            print(f"| {cls} | {len(names)} | " + " | ".join(cells) + f" | {noise * 100:.1f} % |")
            series[(env, cls, DASHES[i % len(DASHES)])] = values
        print(f"\nPer material ({env}; rms at each L, noise-free; gloss; class):\n")
        print("| material | gloss | class | " + " | ".join(f"L={L}" for L in bands) + " |")
        print("|---|---|---|" + "---|" * len(bands))
        for name in sorted(data, key=lambda n: next(iter(data[n].values()))["gloss"]):
            g = next(iter(data[name].values()))["gloss"]
            print(f"| {name.replace('.binary', '')} | {g:.2f} | {klass(g)} | " +
                  " | ".join(f"{data[name][L]['rms'] * 100:.1f}" for L in bands) + " |")
    svg(series, bands, args.output)


if __name__ == "__main__":
    main()
