"""MERL files and numpy arrays: round trips, conventions, errors, distances."""
import numpy as np
import pytest

import matlas
from conftest import DIMS, smooth_table

SCALE = np.array([1.0 / 1500, 1.15 / 1500, 1.66 / 1500])


def test_stored_units_round_trip_bit_exact(tmp_path):
    rng = np.random.default_rng(2)
    stored = rng.uniform(0, 1000, (3,) + DIMS)
    stored[1, 2, 3, 4] = -1.0  # missing
    matlas.write_merl(tmp_path / "a.binary", stored, physical=False, allow_nonstandard_dims=True)
    back = matlas.read_merl(tmp_path / "a.binary", physical=False)
    assert back.shape == (3,) + DIMS and back.dtype == np.float64
    assert np.array_equal(back, stored)
    # The file is MERL's layout: int32 dims, then the red, green and blue blocks.
    raw = (tmp_path / "a.binary").read_bytes()
    assert np.frombuffer(raw[:12], "<i4").tolist() == list(DIMS)
    assert np.array_equal(np.frombuffer(raw[12:], "<f8"), stored.ravel())


def test_physical_values_use_the_channel_scales_and_nan_for_missing(tmp_path):
    stored = np.full((3,) + DIMS, 1500.0)
    stored[0, 0, 0, 0] = -1.0
    matlas.write_merl(tmp_path / "s.binary", stored, physical=False, allow_nonstandard_dims=True)
    phys = matlas.read_merl(tmp_path / "s.binary")
    assert np.isnan(phys[0, 0, 0, 0])
    assert np.allclose(phys[:, 1, 1, 1], SCALE * 1500)
    # Physical in, physical out; NaN written as missing.
    matlas.write_merl(tmp_path / "p.binary", phys, allow_nonstandard_dims=True)
    assert np.array_equal(matlas.read_merl(tmp_path / "p.binary", physical=False), stored)


def test_arrays_own_their_memory_without_a_copy(tmp_path):
    t = smooth_table(0.3, 0.4)
    matlas.write_merl(tmp_path / "t.binary", t, allow_nonstandard_dims=True)
    a = matlas.read_merl(tmp_path / "t.binary")
    assert not a.flags["OWNDATA"] and a.base is not None and a.flags["C_CONTIGUOUS"]
    a2 = a.copy()
    del a
    assert np.allclose(a2, t, rtol=1e-15, atol=0)


def test_errors_name_the_file_and_the_problem(tmp_path):
    with pytest.raises(matlas.Error, match="nope.binary: no such file"):
        matlas.read_merl(tmp_path / "nope.binary")
    (tmp_path / "short.binary").write_bytes(b"\x5a\x00\x00\x00")
    with pytest.raises(matlas.Error, match="short.binary: truncated"):
        matlas.read_merl(tmp_path / "short.binary")
    with pytest.raises(matlas.Error, match="refusing to write a 6x6x12 table"):
        matlas.write_merl(tmp_path / "x.binary", smooth_table(0.1, 0.1))
    with pytest.raises(ValueError, match="shape"):
        matlas.write_merl(tmp_path / "x.binary", np.zeros((2, 3)))
    with pytest.raises(ValueError, match="infinite"):
        bad = smooth_table(0.1, 0.1)
        bad[0, 0, 0, 0] = np.inf
        matlas.write_merl(tmp_path / "x.binary", bad, allow_nonstandard_dims=True)


def test_distances_are_metrics(tmp_path):
    a, b, c = (smooth_table(p, 0.5) for p in (0.1, 0.5, 0.9))
    d = matlas.brdf_distance
    assert d(a, a) == {"cbrt_cosine": 0.0, "cosine_rmse": 0.0, "values": d(a, a)["values"]}
    assert d(a, a)["values"] > 0
    for key in ("cbrt_cosine", "cosine_rmse"):
        assert d(a, b)[key] == pytest.approx(d(b, a)[key], rel=1e-12)
        assert d(a, c)[key] <= d(a, b)[key] + d(b, c)[key] + 1e-12
        assert d(a, b)[key] > 0
    # File paths work as well as arrays.
    matlas.write_merl(tmp_path / "a.binary", a, allow_nonstandard_dims=True)
    assert d(tmp_path / "a.binary", a)["cosine_rmse"] == pytest.approx(0.0, abs=1e-15)
