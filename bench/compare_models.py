#!/usr/bin/python3
"""Compares two matlas models tensor by tensor (bitwise, else the max abs difference and relative
to the largest magnitude), e.g. a single-process build and `mpirun -np P matlas build` of the same
files. Standard library only (the differences are computed only for tensors that are not bitwise
equal). Usage: bench/compare_models.py A.matlas B.matlas"""
import array
import json
import math
import struct
import sys

CODES = {"F64": "d", "F32": "f", "I32": "i"}


def read(path):
    with open(path, "rb") as f:
        (length,) = struct.unpack("<Q", f.read(8))
        header = json.loads(f.read(length))
        base = 8 + length
        out = {}
        for name, t in header.items():
            if name == "__metadata__":
                continue
            begin, end = t["data_offsets"]
            f.seek(base + begin)
            out[name] = (t["dtype"], tuple(t["shape"]), f.read(end - begin))
        return out, json.loads(header["__metadata__"]["matlas"])


def values(dtype, raw):
    if dtype == "F16":
        return [v[0] for v in struct.iter_unpack("<e", raw)]
    a = array.array(CODES[dtype])
    a.frombytes(raw)
    return a


(a, meta_a), (b, meta_b) = read(sys.argv[1]), read(sys.argv[2])
for name in sorted(a):
    (ta, sa, ra), (tb, sb, rb) = a[name], b[name]
    if sa != sb or ta != tb:
        print(f"{name:12s} shapes or types differ: {ta}{sa} vs {tb}{sb}")
        continue
    if ra == rb:
        print(f"{name:12s} {str(sa):18s} bitwise yes")
        continue
    x, y = values(ta, ra), values(tb, rb)
    d = max(abs(u - v) for u, v in zip(x, y))
    scale = max(abs(u) for u in x)
    print(f"{name:12s} {str(sa):18s} bitwise no   max |a-b| {d:.3e}  relative to max |a| {d / scale if scale else 0:.3e}")

# The latent layout up to rotation (the likelihood and the priors depend only on distances): the
# pairwise distances, and the log-likelihood each build reached.
def distances(entry):
    dtype, shape, raw = entry
    x = values(dtype, raw)
    n, q = shape
    rows = [x[i * q:(i + 1) * q] for i in range(n)]
    return [math.dist(rows[i], rows[j]) for i in range(n) for j in range(n)]


da, db = distances(a["latent"]), distances(b["latent"])
worst = max(abs(u - v) for u, v in zip(da, db))
print(f"latent pairwise distances: max |a-b| {worst:.3e}  relative to max {worst / max(da):.3e}")
la, lb = meta_a["log_likelihood"], meta_b["log_likelihood"]
print(f"log-likelihood: {la:.10g} vs {lb:.10g} (relative difference {abs(la - lb) / abs(la):.2e})")
