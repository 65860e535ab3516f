"""Sparse samples from Python (issue 30): Model.fit_samples, Model.sample_plan, read_samples."""
import numpy as np
import pytest

import matlas


def random_directions(rng, count):
    """Uniform directions of the upper hemisphere below about 80 degrees, (count, 3)."""
    z = 0.18 + 0.82 * rng.uniform(size=count)
    phi = 2 * np.pi * rng.uniform(size=count)
    s = np.sqrt(1 - z * z)
    return np.stack([s * np.cos(phi), s * np.sin(phi), z], axis=1)


def samples_of(model, index, count, seed=3):
    """`count` samples of input `index` (its own table, read through the model's bins) where the
    model keeps data."""
    rng = np.random.default_rng(seed)
    wi, wo = random_directions(rng, 4 * count), random_directions(rng, 4 * count)
    rgb = model.evaluate(model.latent[index], wi, wo)
    keep = np.flatnonzero((rgb > 0).all(axis=1))[:count]
    assert len(keep) == count
    return wi[keep], wo[keep], rgb[keep]


def test_samples_of_an_input_land_on_it(model):
    wi, wo, rgb = samples_of(model, 5, 25)
    fit = model.fit_samples(wi, wo, rgb)
    extent = model.latent.max(axis=0) - model.latent.min(axis=0)
    np.testing.assert_allclose(fit["x"], model.latent[5], atol=0.02 * extent.max())
    assert fit["best_input"] == model.names[5]
    assert fit["best_index"] == 5
    assert fit["used"] == 25
    assert fit["residual"].shape == (25, 3)
    assert np.nanmax(np.abs(fit["residual"])) < 1e-3
    assert fit["latent_covariance"].shape == (model.q, model.q)
    assert fit["outliers"] == [] and not fit["is_outlier"].any()
    assert fit["weights"].shape == (model.n,)
    # The fitted table is the input's (within the fit's tolerance), and the table at x unless the
    # combination stage chose a mix off the map.
    t, ref = model.table_for_weights(fit["weights"]), model.material_table(5)
    assert np.nanmax(np.abs(t - ref)) <= 0.05 * np.nanmax(np.abs(ref))
    if not fit["combined"]:
        np.testing.assert_allclose(t, model.table(fit["x"]), rtol=1e-9, atol=1e-12)
    with pytest.raises(ValueError, match="one per input"):
        model.table_for_weights(np.ones(model.n + 1))


def test_a_corrupted_sample_is_an_outlier_and_ratios_convert(model):
    wi, wo, rgb = samples_of(model, 2, 30, seed=8)
    bad = rgb.copy()
    bad[4] *= 10
    fit = model.fit_samples(wi, wo, bad)
    assert fit["outliers"] == [4]
    assert fit["is_outlier"][4]
    assert fit["best_input"] == model.names[2]
    # The same samples as radiance ratios f cos(theta_i), with uncertainties: the same point.
    ratio = model.fit_samples(wi, wo, rgb * wi[:, 2:3], sigma=0.01 * rgb.mean(), quantity="ratio")
    np.testing.assert_allclose(ratio["x"], model.fit_samples(wi, wo, rgb)["x"], atol=1e-3)


def test_bad_samples_raise_naming_the_row(model):
    wi, wo, rgb = samples_of(model, 1, 6)
    below = wi.copy()
    below[3, 2] = -0.2
    with pytest.raises(ValueError, match=r"row 3: wi is at or below the horizon"):
        model.fit_samples(below, wo, rgb)
    negative = rgb.copy()
    negative[2, 1] = -1
    with pytest.raises(ValueError, match=r"row 2: g = -1 is negative"):
        model.fit_samples(wi, wo, negative)
    with pytest.raises(ValueError, match=r"shape \(K, 3\)"):
        model.fit_samples(wi[:, :2], wo, rgb)
    with pytest.raises(ValueError, match="same number of rows"):
        model.fit_samples(wi[:5], wo, rgb)
    with pytest.raises(ValueError, match="quantity"):
        model.fit_samples(wi, wo, rgb, quantity="radiance")
    with pytest.raises(matlas.Error):  # fewer samples than q + 1
        model.fit_samples(wi[:2], wo[:2], rgb[:2])


def test_a_plan_has_k_distinct_directions_and_reads_back(model, tmp_path):
    plan = model.sample_plan(6)
    assert plan["wi"].shape == (6, 3) and plan["wo"].shape == (6, 3)
    assert (plan["wi"][:, 2] > 0).all() and (plan["wo"][:, 2] > 0).all()
    pairs = {tuple(np.round(np.concatenate([a, b]), 6)) for a, b in zip(plan["wi"], plan["wo"])}
    assert len(pairs) == 6
    assert len(plan["gain"]) == 6 and plan["conditioned_on"] == 0
    np.testing.assert_allclose(matlas.directions(plan["theta_i"], plan["phi_i"]), plan["wi"], atol=1e-9)
    # The plan's CSV is a sample file with the directions and no values.
    path = tmp_path / "plan.csv"
    path.write_text(plan["csv"])
    s = matlas.read_samples(path)
    np.testing.assert_allclose(s["wi"], plan["wi"], atol=1e-7)
    assert not s["measured"].any() and np.isnan(s["rgb"]).all()
    # Measured: the next direction is a new one, given those.
    wi, wo, rgb = samples_of(model, 4, 8)
    nxt = model.sample_plan(2, measured={"wi": wi, "wo": wo, "rgb": rgb})
    assert nxt["conditioned_on"] == 8 and nxt["wi"].shape == (2, 3)


def test_read_samples_of_a_file_fits_like_the_arrays(model, tmp_path):
    wi, wo, rgb = samples_of(model, 6, 12)
    lines = ["# samples of input 6", "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z,r,g,b"]
    lines += [",".join(f"{v:.17g}" for v in (*a, *b, *c)) for a, b, c in zip(wi, wo, rgb)]
    lines.append("0,0,1,0.5,0,-0.1,1,1,1")  # line 15: wo below the horizon
    path = tmp_path / "s.csv"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(matlas.Error, match="line 15"):
        matlas.read_samples(path)
    s = matlas.read_samples(path, skip_invalid=True)
    assert len(s["skipped"]) == 1 and s["skipped"][0].startswith("line 15")
    assert s["line"].tolist() == list(range(3, 15))
    np.testing.assert_allclose(s["rgb"], rgb, rtol=1e-12)
    a = model.fit_samples(s["wi"], s["wo"], s["rgb"], s["sigma"])
    b = model.fit_samples(wi, wo, rgb)
    np.testing.assert_allclose(a["x"], b["x"], atol=1e-9)
    assert matlas.parse_samples("\n".join(lines[:5]))["wi"].shape == (3, 3)
