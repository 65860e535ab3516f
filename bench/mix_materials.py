#!/usr/bin/python3
"""Random convex mixtures of measured materials, written as MERL files (bench/make_db1000.sh).

    PYTHONPATH=build/python /usr/bin/python3 bench/mix_materials.py --count 500 --seed 1000 -o DIR SOURCE.binary...

Each mixture draws k = 2 or 3 distinct sources (uniformly) and weights from a flat Dirichlet
(uniform on the simplex), and writes sum_i w_i f_i, the mixture of the physical BRDF values
(linear space, NaN where any source is unmeasured): the BRDF of a surface made of sub-pixel
patches of the sources in the proportions w. It is a valid BRDF (positive, reciprocal, energy
conserving when the sources are) and what a material between two measured ones would look like
under a blend of the two. Names: mix-NNNN-SOURCE1-SOURCE2[-SOURCE3] (shortened to 80 characters).
Reading and writing go through the matlas package (matlas.read_merl / write_merl), so the files
are exactly what the library writes. Deterministic: numpy's PCG64 generator with the seed, the
sources sorted by name, one draw sequence per mixture.
"""
import argparse
import os
import sys

import numpy as np

import matlas


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("sources", nargs="+")
    p.add_argument("-o", "--output", required=True)
    p.add_argument("--count", type=int, required=True)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--max-components", type=int, default=3)
    a = p.parse_args()
    sources = sorted(a.sources, key=os.path.basename)
    if len(sources) < 2:
        print("need at least two sources", file=sys.stderr)
        return 2
    os.makedirs(a.output, exist_ok=True)
    rng = np.random.Generator(np.random.PCG64(a.seed))
    draws = []
    for i in range(a.count):
        k = int(rng.integers(2, a.max_components + 1))
        idx = sorted(int(j) for j in rng.choice(len(sources), size=k, replace=False))
        w = rng.dirichlet(np.ones(k))
        draws.append((i, idx, w))
    # A few recent tables stay in memory; the rest come from the page cache (83 tables, 2.9 GB).
    cache: dict[int, np.ndarray] = {}
    for i, idx, w in draws:
        stems = [os.path.splitext(os.path.basename(sources[j]))[0] for j in idx]
        name = f"mix-{i:04d}-" + "-".join(stems)
        name = name[:80] + ".binary"
        out = os.path.join(a.output, name)
        if os.path.exists(out):
            continue
        table = None
        for j, wj in zip(idx, w):
            if j not in cache:
                if len(cache) > 8:
                    cache.pop(next(iter(cache)))
                cache[j] = matlas.read_merl(sources[j])
            table = wj * cache[j] if table is None else table + wj * cache[j]
        matlas.write_merl(out, table)
    return 0


if __name__ == "__main__":
    sys.exit(main())
