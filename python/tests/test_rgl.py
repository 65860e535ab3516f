"""RGL .bsdf files from Python: a tiny tensor file written here with struct (an independent
writer of the container), evaluated against its closed form and resampled onto the MERL grid."""
import math
import struct

import numpy as np
import pytest

import matlas
from conftest import shared_dir

THETA_I = [0.0, 0.6, 1.2, math.pi / 2]


def refl(c, theta_i, x, y):
    return (1.0 + theta_i) * (0.2 + 0.1 * c + 0.3 * x + 0.1 * y + 0.2 * x * y)


def tensor_file(fields):
    """fields: list of (name, dtype code, shape, bytes)."""
    header = b"tensor_file\0" + struct.pack("<BBI", 1, 0, len(fields))
    size = len(header) + sum(2 + len(n) + 2 + 1 + 8 + 8 * len(s) for n, _, s, _ in fields)
    offset, entries, blobs = size, b"", b""
    for name, dtype, shape, data in fields:
        entries += struct.pack("<H", len(name)) + name.encode() + struct.pack("<HBQ", len(shape), dtype, offset)
        entries += struct.pack(f"<{len(shape)}Q", *shape)
        blobs += data
        offset += len(data)
    return header + entries + blobs


def synthetic_bsdf(n=5, vn=6):
    f32 = lambda a: np.asarray(a, "<f4").tobytes()
    grid = (np.arange(n) / (n - 1))
    rgb = np.array([[[[refl(c, t, x, y) for x in grid] for y in grid] for c in range(3)] for t in THETA_I])[None]
    xs = np.arange(4) / 3
    return tensor_file([
        ("description", 1, [9], b"synthetic"),
        ("phi_i", 10, [1], f32([0.0])),
        ("theta_i", 10, [4], f32(THETA_I)),
        ("ndf", 10, [2, 4], f32([1 + xs, 1 + xs])),
        ("sigma", 10, [2, 4], f32([0.5 + 0.25 * xs] * 2)),
        ("vndf", 10, [1, 4, vn, vn], f32(np.ones((1, 4, vn, vn)))),
        ("rgb", 10, [1, 4, 3, n, n], f32(rgb)),
        ("jacobian", 1, [1], b"\1"),
    ])


def expected(wi, wo):
    m = (wi + wo) / np.linalg.norm(wi + wo)
    ti, tm = math.acos(wi[2]), math.acos(min(1.0, m[2]))
    x = math.sqrt(tm / (math.pi / 2))
    y = (math.atan2(m[1], m[0]) - math.atan2(wi[1], wi[0]) + math.pi) / (2 * math.pi) % 1.0
    xi = math.sqrt(ti / (math.pi / 2))
    return np.array([refl(c, ti, x, y) for c in range(3)]) * (1 + x) / (4 * (0.5 + 0.25 * xi))


def test_synthetic_file_evaluates_to_its_closed_form(tmp_path):
    path = tmp_path / "s.bsdf"
    path.write_bytes(synthetic_bsdf())
    b = matlas.RglBsdf(path)
    assert b.description == "synthetic" and b.isotropic
    rng = np.random.default_rng(4)
    def dirs(k):
        z = rng.uniform(0.05, 1, k); p = rng.uniform(0, 2 * np.pi, k); r = np.sqrt(1 - z * z)
        return np.stack([r * np.cos(p), r * np.sin(p), z], 1)
    wi, wo = dirs(50), dirs(50)
    got = b.eval(wi, wo, cosine=True)
    want = np.array([expected(a, c) for a, c in zip(wi, wo)])
    assert np.allclose(got, want, rtol=1e-5)
    assert np.allclose(b.eval(wi, wo), want / wo[:, 2:3], rtol=1e-5)


def test_bsdf_files_read_as_merl_tables(tmp_path):
    path = tmp_path / "s.bsdf"
    path.write_bytes(synthetic_bsdf())
    t = matlas.read_brdf(path)
    assert t.shape == (3, 90, 90, 180)
    assert np.isnan(t[0]).sum() == 361784  # a direction below the horizon: missing, as in MERL
    assert np.array_equal(t, matlas.RglBsdf(path).resample(), equal_nan=True)


def test_broken_bsdf_files_are_rejected(tmp_path):
    good = synthetic_bsdf()
    for n in (0, 5, 40, len(good) - 1):
        p = tmp_path / f"cut{n}.bsdf"
        p.write_bytes(good[:n])
        with pytest.raises(matlas.Error, match=f"cut{n}.bsdf: "):
            matlas.RglBsdf(p)


def test_real_rgl_material():
    shared = shared_dir()
    if shared is None:
        pytest.skip("../shared/data/rgl is not beside the source tree (set MATLAS_SHARED_DIR)")
    b = matlas.RglBsdf(shared / "data" / "rgl" / "paper_white_rgb.bsdf")
    assert b.description == "White A4 paper (160 gsm)"
    f = b.eval([[0, 0, 1]], [[0.5, 0, math.sqrt(0.75)]])
    assert 0.2 < f[0, 1] < 0.35  # a diffuse white: about 0.84 / pi
