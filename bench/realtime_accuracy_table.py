#!/usr/bin/env python3
"""Markdown tables of docs/REALTIME.md ("Accuracy of the viewer") from bench_zonal_accuracy CSVs.

    bench/realtime_accuracy_table.py before.csv after.csv > tables.md

Each CSV: environment,material,gloss,L,lobes,window,lights,l1,rms,noise (lights: the direct
lights' texel count, 0 without; absent in older files: 0). A configuration is (lobes, window,
lights); the tables give the mean over materials of the noise-free relative RMS error
(rms) per environment and configuration, then per material the mean and largest over the
environments. Classes by gloss as in the study: diffuse < 1 <= glossy < 6 <= mirror-like.
"""
import csv
import sys
from collections import defaultdict


def load(paths):
    rows = []
    for p in paths:
        rows += list(csv.DictReader(open(p)))
    return rows


def label(cfg):
    lobes, window, lights = cfg
    return (("no lobes" if lobes == "0" else f"{lobes} lobes") + f", {window}" +
            ("" if lights == "0" else f", {lights} lights"))


def klass(g):
    return "diffuse" if g < 1 else "glossy" if g < 6 else "mirror-like"


def main():
    rows = load(sys.argv[1:])
    for r in rows:
        r.setdefault("lights", "0")
        r["lights"] = r["lights"] or "0"
    cfgs = sorted({(r["lobes"], r["window"], r["lights"]) for r in rows},
                  key=lambda c: (int(c[2]), c[0], c[1] != "hann"))
    envs = sorted({r["environment"] for r in rows})
    err = defaultdict(dict)  # cfg -> (env, material) -> rms
    gloss = {}
    for r in rows:
        err[(r["lobes"], r["window"], r["lights"])][(r["environment"], r["material"])] = float(r["rms"])
        gloss[r["material"]] = float(r["gloss"])
    mats = sorted(gloss, key=gloss.get)
    print("| environment | " + " | ".join(label(c) for c in cfgs) + " |")
    print("|---|" + "---|" * len(cfgs))
    for e in envs + ["**mean**"]:
        cells = []
        for c in cfgs:
            es = envs if e == "**mean**" else [e]
            v = [err[c][(x, m)] for x in es for m in mats if (x, m) in err[c]]
            cells.append(f"{100 * sum(v) / len(v):.1f} %" if v else "–")
        print(f"| {e if e.startswith('*') else '`' + e + '`'} | " + " | ".join(cells) + " |")
    print()
    print("Per class (mean over materials and environments; largest single value in brackets):")
    print()
    print("| class | materials | " + " | ".join(label(c) for c in cfgs) + " |")
    print("|---|---|" + "---|" * len(cfgs))
    for k in ["diffuse", "glossy", "mirror-like"]:
        ms = [m for m in mats if klass(gloss[m]) == k]
        cells = []
        for c in cfgs:
            v = [(err[c][(x, m)], m, x) for x in envs for m in ms if (x, m) in err[c]]
            if not v:
                cells.append("–")
                continue
            worst = max(v)
            cells.append(f"{100 * sum(a for a, _, _ in v) / len(v):.1f} % ({100 * worst[0]:.0f} %, {worst[1]}/{worst[2]})")
        print(f"| {k} | {len(ms)} | " + " | ".join(cells) + " |")
    print()
    print("Per material (mean over the environments / under `studio`):")
    print()
    print("| material | gloss | class | " + " | ".join(label(c) for c in cfgs) + " |")
    print("|---|---|---|" + "---|" * len(cfgs))
    for m in mats:
        cells = []
        for c in cfgs:
            v = [err[c][(x, m)] for x in envs if (x, m) in err[c]]
            s = err[c].get(("studio", m))
            cells.append(f"{100 * sum(v) / len(v):.1f} / {100 * s:.1f}" if v and s is not None else "–")
        print(f"| {m} | {gloss[m]:.2f} | {klass(gloss[m])} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
