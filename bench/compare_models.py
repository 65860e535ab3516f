#!/usr/bin/python3
"""Compares two matlas models tensor by tensor (max abs difference, and relative to the largest
magnitude), e.g. a single-process build and `mpirun -np P matlas build` of the same files.
Usage: bench/compare_models.py A.matlas B.matlas"""
import json
import struct
import sys

import numpy as np

DTYPES = {"F64": np.float64, "F32": np.float32, "F16": np.float16, "I32": np.int32}


def tensors(path):
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
            out[name] = np.frombuffer(f.read(end - begin), dtype=DTYPES[t["dtype"]]).reshape(t["shape"])
        return out


a, b = tensors(sys.argv[1]), tensors(sys.argv[2])
for name in sorted(a):
    x, y = a[name], b[name]
    if x.shape != y.shape:
        print(f"{name:12s} shapes differ: {x.shape} vs {y.shape}")
        continue
    identical = x.tobytes() == y.tobytes()
    d = np.max(np.abs(x.astype(np.float64) - y.astype(np.float64))) if x.size else 0.0
    scale = np.max(np.abs(x.astype(np.float64))) if x.size else 0.0
    print(f"{name:12s} {str(x.shape):18s} bitwise {'yes' if identical else 'no ':3s}  max |a-b| {d:.3e}"
          f"  relative to max |a| {d / scale if scale else 0:.3e}")

# The latent layout up to rotation (the likelihood and the priors depend only on distances): the
# pairwise distances, and the log-likelihood each build reached.
def distances(x):
    return np.sqrt(((x[:, None, :] - x[None, :, :]) ** 2).sum(-1))


da, db = distances(a["latent"]), distances(b["latent"])
print(f"latent pairwise distances: max |a-b| {np.max(np.abs(da - db)):.3e}  relative to max {np.max(np.abs(da - db)) / np.max(da):.3e}")


def metadata(path):
    with open(path, "rb") as f:
        (length,) = struct.unpack("<Q", f.read(8))
        return json.loads(json.loads(f.read(length))["__metadata__"]["matlas"])


la, lb = metadata(sys.argv[1])["log_likelihood"], metadata(sys.argv[2])["log_likelihood"]
print(f"log-likelihood: {la:.10g} vs {lb:.10g} (relative difference {abs(la - lb) / abs(la):.2e})")
