"""Shared fixtures: a small synthetic database and a model built from it (once per session)."""
import os
import pathlib

import numpy as np
import pytest

import matlas

DIMS = (6, 6, 12)


def smooth_table(a: float, b: float, dims=DIMS) -> np.ndarray:
    """A lobe whose sharpness and colour vary with the hidden parameters (a, b): physical values."""
    th = (np.arange(dims[0]) + 0.5) / dims[0]
    td = (np.arange(dims[1]) + 0.5) / dims[1]
    lobe = np.exp(-th[:, None] ** 2 * (2.0 + 20.0 * a)) * (1.0 + 0.3 * td[None, :] * b)
    lobe = np.broadcast_to(lobe[:, :, None], dims)
    return np.stack([0.05 + (0.5 + 0.4 * np.sin(a * 3 + c + b)) * lobe for c in range(3)])


@pytest.fixture(scope="session")
def database(tmp_path_factory):
    folder = tmp_path_factory.mktemp("db")
    rng = np.random.default_rng(1)
    tables = []
    for i in range(8):
        t = smooth_table(*rng.uniform(0, 1, 2))
        matlas.write_merl(folder / f"mat{i:02d}.binary", t, allow_nonstandard_dims=True)
        tables.append(t)
    return folder, tables


@pytest.fixture(scope="session")
def model(database, tmp_path_factory):
    folder, _ = database
    out = tmp_path_factory.mktemp("model") / "m.matlas"
    return matlas.build(folder, out, dim=2)


def shared_dir():
    """../shared beside the source tree, or None."""
    source = os.environ.get("MATLAS_SOURCE_DIR")
    candidates = [os.environ.get("MATLAS_SHARED_DIR")]
    if source:
        candidates.append(os.path.join(source, "..", "shared"))
    candidates.append(str(pathlib.Path(__file__).resolve().parents[3] / "shared"))
    for c in candidates:
        if c and os.path.isdir(os.path.join(c, "data", "rgl")):
            return pathlib.Path(c)
    return None
