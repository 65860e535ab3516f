"""A model built from Python: exactness at the data points, batch queries, projection, progress."""
import os
import pathlib
import subprocess

import numpy as np
import pytest

import matlas


def test_description(model, database):
    folder, tables = database
    assert model.n == 8 and model.q == 2
    assert model.names == [f"mat{i:02d}" for i in range(8)]
    assert model.latent.shape == (8, 2)
    assert model.dims == tables[0].shape[1:]
    assert isinstance(model.metadata, dict) and model.metadata
    assert "n=8" in repr(model)


def test_weights_are_unit_vectors_at_the_data(model):
    for i in range(model.n):
        w = model.weights(model.latent[i])
        assert np.allclose(w, np.eye(model.n)[i], atol=1e-9)
        assert model.variance(model.latent[i]) == pytest.approx(0.0, abs=1e-9)


def test_tables_reproduce_every_input_at_its_point(model, database):
    _, tables = database
    for i, t in enumerate(tables):
        m = model.table(model.latent[i])
        assert m.shape == t.shape
        assert np.linalg.norm(m - t) / np.linalg.norm(t) < 1e-6
        # The stored input itself (weights exactly e_i): float32 storage, so within 1e-6.
        stored = model.material_table(model.names[i])
        assert np.array_equal(stored, model.material_table(i))
        assert np.abs(stored - t).max() <= 1e-6 * np.abs(t).max()
        assert np.allclose(stored, m, rtol=1e-6, atol=0)


def test_batches_equal_single_queries(model):
    rng = np.random.default_rng(3)
    lo, hi = model.latent.min(0), model.latent.max(0)
    X = lo + (hi - lo) * rng.uniform(0, 1, (4, model.q))
    W = model.weights_batch(X)
    V = model.variance_batch(X)
    T = model.table_batch(X)
    assert W.shape == (4, model.n) and V.shape == (4,) and T.shape == (4, 3) + model.dims
    for r in range(4):
        assert np.array_equal(W[r], model.weights(X[r]))
        assert V[r] == model.variance(X[r])
        assert np.array_equal(T[r], model.table(X[r]), equal_nan=True)
    # The interpolation is the explicit weighted sum of the inputs.
    inputs = np.stack([model.material_table(i) for i in range(model.n)])
    mean = inputs.mean(0)
    explicit = mean + np.tensordot(W[0], inputs - mean, axes=1)
    assert np.allclose(T[0], explicit, rtol=1e-5, atol=1e-9)


def test_wrong_point_sizes_are_refused(model):
    with pytest.raises(ValueError, match="3 coordinates, the model has q = 2"):
        model.weights([0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="columns for q = 2"):
        model.table_batch(np.zeros((2, 3)))


def test_projection_finds_an_input_at_its_own_point(model, database):
    _, tables = database
    p = model.project(tables[5])
    assert p["nearest"] == "mat05" and p["nearest_index"] == 5
    assert p["relative_error"] < 1e-5
    assert np.allclose(model.weights(p["x"]), np.eye(model.n)[5], atol=1e-3)


def test_albedo_curve(model):
    a = model.albedo_curve(model.latent[0])
    assert a.shape == (90, 3) and np.all(a > 0)


def test_build_reports_progress_and_errors(database, tmp_path):
    folder, _ = database
    seen = []
    m = matlas.build([folder], tmp_path / "p.matlas", dim=1, progress=lambda label, done, total: seen.append((label, done, total)))
    assert m.q == 1 and seen
    # Without an output file: a temporary one, gone once the model is open.
    t = matlas.build(folder, dim=1)
    assert t.n == 8 and not pathlib.Path(t.path).exists()
    assert np.array_equal(t.table(t.latent[3]), m.table(m.latent[3]), equal_nan=True)
    assert all(0 <= done <= total for _, done, total in seen if total)

    def fails(label, done, total):
        raise KeyError("stop")

    with pytest.raises(KeyError):
        matlas.build(folder, tmp_path / "q.matlas", dim=1, progress=fails)
    with pytest.raises(matlas.Error, match="at least 2"):
        matlas.build([folder / "mat00.binary"], tmp_path / "r.matlas")
    with pytest.raises(matlas.Error, match="nope"):
        matlas.Model(tmp_path / "nope.matlas")


@pytest.mark.skipif(not os.environ.get("MATLAS_COMMAND"), reason="the matlas command's path is not given")
@pytest.mark.parametrize("dim", [2, 5])
def test_default_build_is_the_commands(database, tmp_path, dim):
    """matlas.build with no options places the latent points exactly as `matlas build` does."""
    folder, _ = database
    from_python = matlas.build(folder, tmp_path / "py.matlas", dim=dim)
    # The same OpenBLAS kernels as this process (numpy loaded the library before matlas could
    # choose them): other kernels round differently and the optimiser takes another path.
    env = dict(os.environ, OPENBLAS_CORETYPE=matlas.blas_kernels())
    subprocess.run([os.environ["MATLAS_COMMAND"], "build", str(folder), "-o", str(tmp_path / "cli.matlas"),
                    "--dim", str(dim), "--quiet"], check=True, capture_output=True, env=env)
    from_command = matlas.Model(tmp_path / "cli.matlas")
    assert np.array_equal(from_python.latent, from_command.latent)
    py, cli = from_python.metadata, from_command.metadata
    for key in ("layout_transform", "kernel", "latent_prior", "interpolation"):
        assert py[key] == cli[key], key
    assert py["layout_transform"] == "cosine-cbrt"
    for key in ("method", "iterations", "converged"):
        assert py["optimizer"][key] == cli["optimizer"][key], key


@pytest.mark.skipif(not os.environ.get("MATLAS_COMMAND"), reason="the matlas command's path is not given")
def test_coarse_and_sparse_builds_are_the_commands(database, tmp_path):
    """coarse= and sparse_inducing= place the points as `matlas build --coarse` / `--sparse-inducing` do."""
    folder, _ = database
    env = dict(os.environ, OPENBLAS_CORETYPE=matlas.blas_kernels())
    for kwargs, flags, expect in (({"coarse": 4}, ["--coarse", "4"], {"method": "exact", "coarse": 4}),
                                  ({"sparse_inducing": 3}, ["--sparse-inducing", "3"], {"method": "sparse"})):
        from_python = matlas.build(folder, tmp_path / "py.matlas", dim=2, max_iterations=200, **kwargs)
        subprocess.run([os.environ["MATLAS_COMMAND"], "build", str(folder), "-o", str(tmp_path / "cli.matlas"),
                        "--dim", "2", "--max-iterations", "200", "--quiet", *flags], check=True,
                       capture_output=True, env=env)
        from_command = matlas.Model(tmp_path / "cli.matlas")
        assert np.array_equal(from_python.latent, from_command.latent), flags
        placement = from_python.metadata["latent_optimization"]
        assert placement == from_command.metadata["latent_optimization"]
        for key, value in expect.items():
            assert placement[key] == value, (flags, placement)
    with pytest.raises(matlas.Error, match="coarse"):
        matlas.build(folder, tmp_path / "bad.matlas", coarse=-2)
