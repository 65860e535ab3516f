"""matlas: Gaussian-process manifolds of measured BRDFs, from Python.

A map (``.matlas`` file) is built from MERL ``.binary`` and RGL ``.bsdf`` measured materials;
every point of it is a full BRDF table. Tables are float64 numpy arrays of shape
``(3, theta_h, theta_d, phi_d)`` (90 x 90 x 180 for MERL), channel-major like MERL files:
physical values with NaN where nothing is measured (default), or MERL's stored units with -1
(``physical=False``, bit-exact with the files).

    >>> import matlas
    >>> model = matlas.build("merl/", "m.matlas", dim=2)
    >>> f = model.table(model.latent[0])          # material 0, exactly
    >>> model.project("paper_white_rgb.bsdf")["nearest"]

See docs/PYTHON.md.
"""
from __future__ import annotations

import json as _json

import numpy as _np

from ._matlas import (Error, Model, RglBsdf, blas_kernels, brdf_distance, build, parse_samples, read_merl,
                      read_samples, write_merl)

__all__ = ["Error", "Model", "RglBsdf", "blas_kernels", "brdf_distance", "build", "directions", "parse_samples",
           "read_merl", "read_samples", "write_merl", "read_brdf"]

#: read_merl reads RGL .bsdf files too (resampled onto the MERL grid); this name says so.
read_brdf = read_merl


def _metadata(self: Model) -> dict:
    """The model header's metadata (names, kernel, optimiser, likelihood, sources, ...)."""
    return _json.loads(self.metadata_json)


Model.metadata = property(_metadata)  # type: ignore[attr-defined]


def _repr(self: Model) -> str:
    return f"matlas.Model({str(self.path)!r}: n={self.n}, q={self.q}, grid {self.dims})"


Model.__repr__ = _repr  # type: ignore[assignment]


def directions(theta, phi):
    """Unit directions (K, 3) in the surface's frame (normal +z) from angles in degrees, as sample
    files read theta_i, phi_i (or theta_o, phi_o): (sin t cos p, sin t sin p, cos t)."""
    t = _np.radians(_np.asarray(theta, dtype=float))
    p = _np.radians(_np.asarray(phi, dtype=float))
    t, p = _np.broadcast_arrays(_np.atleast_1d(t), _np.atleast_1d(p))
    return _np.stack([_np.sin(t) * _np.cos(p), _np.sin(t) * _np.sin(p), _np.cos(t)], axis=-1)
