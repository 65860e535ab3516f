#!/usr/bin/python3
"""Python overhead of Model.table(x): the Python call (weights, table, the numpy array with the
physical-unit conversion) against the same weights() + table() timed inside C++.

    PYTHONPATH=build/python bench/python_table_overhead.py MODEL.matlas [REPEATS]

Prints the medians over REPEATS rounds (default 15; each round times both, alternating, at the
same point between materials) and their ratio (target: within 1.2).
"""
import statistics
import sys
import time

import numpy as np

import matlas


def main(path, repeats=15):
    model = matlas.Model(path)
    x = 0.5 * (model.latent[0] + model.latent[1])
    model.table(x)  # warm the mapping and the allocator
    py, py_stored, cpp = [], [], []
    for _ in range(repeats):
        t = time.perf_counter()
        a = model.table(x)
        py.append(time.perf_counter() - t)
        del a
        t = time.perf_counter()
        a = model.table(x, physical=False)
        py_stored.append(time.perf_counter() - t)
        del a
        cpp.append(model._table_seconds(x, 1))
    p, s, c = statistics.median(py), statistics.median(py_stored), statistics.median(cpp)
    print(f"{model!r}")
    print(f"  C++ weights()+table()        {1e3 * c:8.2f} ms")
    print(f"  Python table(x)              {1e3 * p:8.2f} ms  ({p / c:.2f}x)")
    print(f"  Python table(x, physical=False) {1e3 * s:5.2f} ms  ({s / c:.2f}x)")


if __name__ == "__main__":
    main(sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 15)
