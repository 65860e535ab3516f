"""Type stubs of the matlas package (the pybind11 module matlas._matlas and its Python layer)."""
from os import PathLike
from typing import Any, Callable, Iterable, Optional, TypedDict, Union

import numpy as np
import numpy.typing as npt

_Path = Union[str, PathLike[str]]
_Table = npt.NDArray[np.float64]  # (3, theta_h, theta_d, phi_d)
_Points = npt.ArrayLike  # (m, q)

class Error(RuntimeError):
    """Bad input: the message names the file or argument and the problem."""

class Projection(TypedDict):
    x: npt.NDArray[np.float64]
    relative_error: float
    residual2: float
    variance: float
    nearest: str
    nearest_index: int
    nearest_relative_error: float
    missing: int

class Distance(TypedDict):
    cbrt_cosine: float
    cosine_rmse: float
    values: int

class SampleFit(TypedDict):
    x: npt.NDArray[np.float64]
    weights: npt.NDArray[np.float64]
    coefficients: npt.NDArray[np.float64]
    variance: float
    latent_covariance: npt.NDArray[np.float64]  # (q, q)
    residual: npt.NDArray[np.float64]  # (K, 3), NaN for rows not fitted
    predicted: npt.NDArray[np.float64]
    weight: npt.NDArray[np.float64]
    outliers: list[int]
    is_outlier: npt.NDArray[np.bool_]
    best_input: Optional[str]
    best_index: int
    combined: bool  # the fitted table is a convex mix of the inputs off the map (weights)
    map_coefficients: npt.NDArray[np.float64]
    combination_strength: float
    input_loss: npt.NDArray[np.float64]
    loss: float
    scale: float
    used: int
    unusable: list[str]
    transform: str
    evaluations: int

class SamplePlan(TypedDict):
    wi: npt.NDArray[np.float64]  # (k, 3)
    wo: npt.NDArray[np.float64]
    theta_i: npt.NDArray[np.float64]  # (k,) degrees
    phi_i: npt.NDArray[np.float64]
    theta_o: npt.NDArray[np.float64]
    phi_o: npt.NDArray[np.float64]
    gain: list[float]
    remaining: list[float]
    conditioned_on: int
    csv: str

class Samples(TypedDict):
    wi: npt.NDArray[np.float64]  # (K, 3) unit directions
    wo: npt.NDArray[np.float64]
    rgb: npt.NDArray[np.float64]  # (K, 3) BRDF values, NaN where not measured
    sigma: npt.NDArray[np.float64]  # (K, 3), 0: unknown
    measured: npt.NDArray[np.bool_]
    line: npt.NDArray[np.int32]
    skipped: list[str]
    json: bool

class Model:
    """A built material map (.matlas file), opened read-only (memory-mapped)."""
    def __init__(self, path: _Path) -> None: ...
    @property
    def path(self) -> PathLike[str]: ...
    @property
    def names(self) -> list[str]: ...
    @property
    def latent(self) -> npt.NDArray[np.float64]:
        """(n, q) latent points, row i for material i."""
    @property
    def q(self) -> int: ...
    @property
    def n(self) -> int: ...
    @property
    def dims(self) -> tuple[int, int, int]: ...
    @property
    def kept_columns(self) -> int: ...
    @property
    def storage(self) -> str: ...
    @property
    def metadata_json(self) -> str: ...
    @property
    def metadata(self) -> dict[str, Any]: ...
    def index_of(self, name: str) -> int: ...
    def weights(self, x: npt.ArrayLike) -> npt.NDArray[np.float64]:
        """w(x), length n; e_i at material i's latent point."""
    def weights_batch(self, X: _Points) -> npt.NDArray[np.float64]:
        """(m, n) weights of the rows of an (m, q) array."""
    def variance(self, x: npt.ArrayLike) -> float: ...
    def variance_batch(self, X: _Points) -> npt.NDArray[np.float64]: ...
    def table(self, x: npt.ArrayLike, physical: bool = True) -> _Table:
        """m(x) as a (3, theta_h, theta_d, phi_d) array (no copy); NaN at dropped columns."""
    def table_batch(self, X: _Points, physical: bool = True) -> npt.NDArray[np.float64]:
        """(m, 3, theta_h, theta_d, phi_d) tables of the rows of an (m, q) array."""
    def material_table(self, material: Union[str, int], physical: bool = True) -> _Table: ...
    def albedo_curve(self, x: npt.ArrayLike) -> npt.NDArray[np.float64]:
        """(90, 3) directional albedo at view angles 0.5, 1.5, ... 89.5 degrees."""
    def project(self, table: Union[_Table, _Path], physical: bool = True, starts: int = 5) -> Projection: ...
    def fit_samples(
        self,
        wi: npt.ArrayLike,
        wo: npt.ArrayLike,
        rgb: npt.ArrayLike,
        sigma: Optional[npt.ArrayLike] = None,
        quantity: str = "brdf",
        robust: bool = True,
    ) -> SampleFit:
        """The map point that best explains (K, 3) measurements; ValueError names a bad row."""
    def table_for_weights(self, weights: npt.ArrayLike, physical: bool = True) -> _Table:
        """The table of weights over the inputs (fit_samples' weights: the fitted table)."""
    def evaluate(self, x: npt.ArrayLike, wi: npt.ArrayLike, wo: npt.ArrayLike) -> npt.NDArray[np.float64]:
        """(K, 3) f(wi, wo) of m(x) by nearest-bin lookup."""
    def sample_plan(self, k: int, measured: Optional[dict[str, Any]] = None) -> SamplePlan:
        """The k directions to measure (given `measured`, as read_samples returns: the next ones)."""
    def _table_seconds(self, x: npt.ArrayLike, repeats: int = 5) -> float: ...

class RglBsdf:
    """An RGL measured material (.bsdf file)."""
    def __init__(self, path: _Path) -> None: ...
    @property
    def description(self) -> str: ...
    @property
    def isotropic(self) -> bool: ...
    @property
    def summary(self) -> str: ...
    def eval(self, wi: npt.ArrayLike, wo: npt.ArrayLike, cosine: bool = False) -> npt.NDArray[np.float64]:
        """(m, 3) RGB values for (m, 3) arrays of directions."""
    def resample(self, physical: bool = True) -> _Table: ...

def build(
    inputs: Union[_Path, Iterable[_Path]],
    output: Optional[_Path] = None,
    *,
    dim: int = 2,
    nugget: float = 1e-4,
    optimizer: str = "lbfgs",
    layout: str = "cosine-cbrt",
    storage: str = "f32",
    starts: int = 0,
    max_iterations: int = 5000,
    coarse: int = 0,
    sparse_inducing: int = 0,
    progress: Optional[Callable[[str, int, int], Any]] = None,
) -> Model: ...
def blas_kernels() -> str:
    """The OpenBLAS kernels builds and queries run on ("SkylakeX", "Haswell", "Prescott", ...)."""
    ...
def read_samples(path: _Path, skip_invalid: bool = False) -> Samples: ...
def parse_samples(text: str, name: str = "samples", skip_invalid: bool = False) -> Samples: ...
def directions(theta: npt.ArrayLike, phi: npt.ArrayLike) -> npt.NDArray[np.float64]:
    """(K, 3) unit directions from angles in degrees (normal +z)."""
def read_merl(path: _Path, physical: bool = True) -> _Table: ...
def read_brdf(path: _Path, physical: bool = True) -> _Table: ...
def write_merl(path: _Path, table: npt.ArrayLike, physical: bool = True, allow_nonstandard_dims: bool = False) -> None: ...
def brdf_distance(a: Union[_Table, _Path], b: Union[_Table, _Path], physical: bool = True) -> Distance: ...
