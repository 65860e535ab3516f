"""Hostile input through the Python package (issue 28): crafted models refused on open, a model
truncated while it is read, values the MERL reader refuses, NaN points in batches."""
import json
import shutil
import struct

import numpy as np
import pytest

import matlas

from conftest import smooth_table


def _rewrite_metadata(path, edit):
    """Rewrites the matlas metadata of a model file: edit(text) -> new text, any length."""
    data = path.read_bytes()
    (n,) = struct.unpack("<Q", data[:8])
    header = json.loads(data[8:8 + n])
    header["__metadata__"]["matlas"] = edit(header["__metadata__"]["matlas"])
    text = json.dumps(header).encode()
    text += b" " * ((-(len(text) + 8)) % 64)
    path.write_bytes(struct.pack("<Q", len(text)) + text + data[8 + n:])


def test_metadata_nested_too_deep_is_refused_on_open(model, tmp_path):
    crafted = tmp_path / "crafted.matlas"
    shutil.copyfile(model.path, crafted)
    _rewrite_metadata(crafted, lambda t: t[:-1] + ',"deep":' + "[" * 100000 + "]" * 100000 + "}")
    with pytest.raises(matlas.Error, match="crafted.matlas: corrupted model metadata: JSON nested more than 64"):
        matlas.Model(crafted)


def test_a_permuted_grid_is_refused_on_open(model, tmp_path):
    crafted = tmp_path / "crafted.matlas"
    shutil.copyfile(model.path, crafted)

    def permute(text):
        meta = json.loads(text)
        meta["grid"] = [meta["grid"][2], meta["grid"][1], meta["grid"][0]]
        return json.dumps(meta)

    _rewrite_metadata(crafted, permute)
    with pytest.raises(matlas.Error, match=r"crafted.matlas: corrupted model metadata: 'grid' \[12, 6, 6\]"):
        matlas.Model(crafted)


def test_a_model_truncated_while_it_is_read_raises_instead_of_answering(model, tmp_path):
    victim = tmp_path / "victim.matlas"
    shutil.copyfile(model.path, victim)
    m = matlas.Model(victim)
    x = m.latent[0]
    good = m.table(x)
    with open(victim, "r+b") as f:
        f.truncate(victim.stat().st_size // 2)
    for call in (lambda: m.table(x), lambda: m.material_table(0), lambda: m.table_batch(m.latent[:2]),
                 lambda: m.project(good), lambda: m.weights(x), lambda: m.variance_batch(m.latent[:2])):
        with pytest.raises(matlas.Error, match="victim.matlas: the model file changed or was truncated while it was read"):
            call()


def test_write_merl_refuses_values_the_reader_refuses(tmp_path):
    for value, physical in ((3e38, True), (1e300, True), (2e15, False)):
        bad = smooth_table(0.1, 0.1)
        bad[1, 2, 3, 4] = value
        with pytest.raises(ValueError, match=r"absurd value .* \(channel 1, bin"):
            matlas.write_merl(tmp_path / "x.binary", bad, physical=physical, allow_nonstandard_dims=True)
        assert not (tmp_path / "x.binary").exists()
    # The largest value the reader accepts is written and read back.
    ok = smooth_table(0.1, 0.1)
    ok[0, 0, 0, 0] = 1e15
    matlas.write_merl(tmp_path / "ok.binary", ok, physical=False, allow_nonstandard_dims=True)
    assert matlas.read_merl(tmp_path / "ok.binary", physical=False)[0, 0, 0, 0] == 1e15


def test_batches_refuse_a_nan_point_as_single_queries_do(model):
    X = np.array([model.latent[0], [np.nan, 0.0]])
    for batch in (model.variance_batch, model.weights_batch, model.table_batch):
        with pytest.raises(ValueError, match="NaN or infinite coordinate"):
            batch(X)
    with pytest.raises(ValueError, match="NaN or infinite coordinate"):
        model.variance(X[1])
