#!/usr/bin/env python3
"""The accuracy table of `BASELINE=1 bench/export_bsdf_accuracy.sh` as a picture (docs/EXPORT.md):
per material, the relative RMS of the file with point samples (x) against the fitted file (y), at
the bin centres and between them, on log axes, with y = x and the 2 % goal.

    bench/export_bsdf_plot.py TABLE.md -o docs/images/export-bsdf-rms.svg
"""
import math
import os
import sys


def rows(path):
    out = []
    for line in open(path):
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 9 or not cells[2].replace(".", "", 1).isdigit():
            continue
        out.append((cells[0], float(cells[2]), float(cells[3]), float(cells[7]), float(cells[8])))
    return out


def main():
    if len(sys.argv) != 4 or sys.argv[2] != "-o":
        sys.exit(__doc__)
    data = rows(sys.argv[1])
    if not data:
        sys.exit(f"{sys.argv[1]}: no rows with the point samples' columns (run with BASELINE=1)")
    lo, hi = 0.1, 30.0
    left, top, size = 70, 30, 420
    def px(v):
        return left + size * (math.log10(min(max(v, lo), hi)) - math.log10(lo)) / (math.log10(hi) - math.log10(lo))
    def py(v):
        return top + size - (px(v) - left)
    svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{left + size + 200}" height="{top + size + 60}" '
           'font-family="sans-serif" font-size="12">', '<rect width="100%" height="100%" fill="white"/>']
    for v in (0.1, 0.3, 1, 2, 3, 10, 30):
        svg.append(f'<line x1="{px(v):.1f}" x2="{px(v):.1f}" y1="{top}" y2="{top + size}" stroke="#ddd"/>')
        svg.append(f'<line x1="{left}" x2="{left + size}" y1="{py(v):.1f}" y2="{py(v):.1f}" stroke="#ddd"/>')
        svg.append(f'<text x="{px(v):.1f}" y="{top + size + 16}" text-anchor="middle">{v:g}</text>')
        svg.append(f'<text x="{left - 6}" y="{py(v) + 4:.1f}" text-anchor="end">{v:g}</text>')
    svg.append(f'<line x1="{px(lo):.1f}" y1="{py(lo):.1f}" x2="{px(hi):.1f}" y2="{py(hi):.1f}" stroke="#888" stroke-dasharray="4 3"/>')
    svg.append(f'<line x1="{left}" x2="{left + size}" y1="{py(2):.1f}" y2="{py(2):.1f}" stroke="#c33" stroke-dasharray="6 3"/>')
    for _, rms, between, point_rms, point_between in data:
        svg.append(f'<circle cx="{px(point_between):.1f}" cy="{py(between):.1f}" r="3.5" fill="none" stroke="#e69f00"/>')
        svg.append(f'<circle cx="{px(point_rms):.1f}" cy="{py(rms):.1f}" r="3.5" fill="#0072b2"/>')
    svg.append(f'<text x="{left + size / 2}" y="{top + size + 40}" text-anchor="middle">relative RMS %, point samples</text>')
    svg.append(f'<text transform="translate(20,{top + size / 2}) rotate(-90)" text-anchor="middle">relative RMS %, fitted samples</text>')
    lx = left + size + 20
    svg.append(f'<circle cx="{lx}" cy="{top + 10}" r="3.5" fill="#0072b2"/><text x="{lx + 10}" y="{top + 14}">at the bin centres</text>')
    svg.append(f'<circle cx="{lx}" cy="{top + 30}" r="3.5" fill="none" stroke="#e69f00"/><text x="{lx + 10}" y="{top + 34}">between them</text>')
    svg.append(f'<line x1="{lx - 6}" x2="{lx + 6}" y1="{top + 50}" y2="{top + 50}" stroke="#888" stroke-dasharray="4 3"/><text x="{lx + 10}" y="{top + 54}">no change</text>')
    svg.append(f'<line x1="{lx - 6}" x2="{lx + 6}" y1="{top + 70}" y2="{top + 70}" stroke="#c33" stroke-dasharray="6 3"/><text x="{lx + 10}" y="{top + 74}">2 % goal</text>')
    svg.append(f'<text x="{lx - 6}" y="{top + 100}">{len(data)} materials</text>')
    svg.append("</svg>")
    out = sys.argv[3]
    with open(out + ".tmp", "w") as f:
        f.write("\n".join(svg) + "\n")
    os.replace(out + ".tmp", out)


if __name__ == "__main__":
    main()
