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

from ._matlas import Error, Model, RglBsdf, blas_kernels, brdf_distance, build, read_merl, write_merl

__all__ = ["Error", "Model", "RglBsdf", "blas_kernels", "brdf_distance", "build", "read_merl", "write_merl", "read_brdf"]

#: read_merl reads RGL .bsdf files too (resampled onto the MERL grid); this name says so.
read_brdf = read_merl


def _metadata(self: Model) -> dict:
    """The model header's metadata (names, kernel, optimiser, likelihood, sources, ...)."""
    return _json.loads(self.metadata_json)


Model.metadata = property(_metadata)  # type: ignore[attr-defined]


def _repr(self: Model) -> str:
    return f"matlas.Model({str(self.path)!r}: n={self.n}, q={self.q}, grid {self.dims})"


Model.__repr__ = _repr  # type: ignore[assignment]
