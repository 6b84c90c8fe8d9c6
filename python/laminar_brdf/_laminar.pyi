"""Type stubs of the native module."""

from os import PathLike
from typing import Any, Literal, Mapping, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

#: Every option value the library accepts (the Rust parsers' names).
Model = Literal["exp", "gauss", "exp2", "gauss2", "rh-exp", "rh-gauss", "jensen", "oren-nayar"]
LayeredModel = Literal["exp", "gauss", "exp2", "gauss2", "rh-exp", "rh-gauss"]
Objective = Literal["free", "paper"]
Uncertainty = Literal["off", "profile", "jacobian", "both", "bootstrap"]
Quantity = Literal["brdf", "radiance"]
AngleUnit = Literal["rad", "deg"]
Precision = Literal["f64", "f32"]
Noise = Literal["given", "equal", "relative"]

Array = npt.NDArray[np.float64]
AxisSpec = Union[str, Sequence[float]]
Grid = Optional[Mapping[str, AxisSpec]]

BATCH_COLUMNS: list[str]
BATCH_DTYPES: list[tuple[str, str]]

def batch_fields(model: LayeredModel = "exp") -> list[tuple[str, str]]: ...
FLAG_BITS: dict[str, int]
MODELS: dict[Model, dict[str, object]]
GRID_AXES: list[str]

def evaluate(
    model: LayeredModel,
    theta_i: Array,
    theta_s: Array,
    phi_s: Array,
    slope: Array,
    beta: Array,
    n: Array,
    a: Array,
    sub_slope: Optional[Array] = None,
    precision: Precision = "f64",
) -> dict[str, Array]: ...
def paper_angles(theta_i: float, phi_i: float, theta_v: float, phi_v: float) -> tuple[float, float, float]: ...
def simd_path() -> str:
    """The lanes the fitting kernels run with: ``"avx2"`` or ``"portable"``
    (``LAMINAR_SIMD`` forces one; every path gives the same bits). Raises
    ``ValueError`` when ``LAMINAR_SIMD`` names no path or one this processor
    cannot run."""
    ...

class Measurements:
    @staticmethod
    def from_arrays(
        theta_i: Array,
        phi_i: Array,
        theta_v: Array,
        phi_v: Array,
        values: Array,
        sigma: Optional[Array] = None,
        quantity: Quantity = "brdf",
        name: str = "arrays",
    ) -> Measurements: ...
    @staticmethod
    def from_csv(
        path: Union[str, PathLike[str]],
        channel: Optional[str] = None,
        angles: AngleUnit = "rad",
        quantity: Quantity = "brdf",
    ) -> Measurements: ...
    @staticmethod
    def from_astm(path: Union[str, PathLike[str]], channel: Optional[str] = None) -> Measurements: ...
    @staticmethod
    def from_nist(path: Union[str, PathLike[str]], channel: Optional[str] = None) -> Measurements: ...
    @staticmethod
    def from_rgl(path: Union[str, PathLike[str]], channel: Optional[str] = None) -> Measurements: ...
    @staticmethod
    def from_curet(dir: Union[str, PathLike[str]], sample: int, channel: str = "avg") -> Measurements: ...
    @staticmethod
    def from_merl(
        path: Union[str, PathLike[str]],
        sample_at: Union[str, PathLike[str]],
        channel: Optional[str] = None,
        angles: AngleUnit = "rad",
    ) -> Measurements: ...
    def with_specular_tolerance(self, tolerance: float) -> Measurements: ...
    @property
    def channels(self) -> list[str]: ...
    @property
    def channel(self) -> str: ...
    def __len__(self) -> int: ...

class FitResult:
    @property
    def model(self) -> str: ...
    @property
    def params(self) -> dict[str, float]: ...
    @property
    def rms(self) -> float: ...
    @property
    def chi2_dof(self) -> Optional[float]: ...
    @property
    def rh(self) -> Optional[dict[str, object]]: ...
    @property
    def grid_params(self) -> dict[str, float]: ...
    @property
    def rms_grid(self) -> float: ...
    @property
    def rms_refined(self) -> Optional[float]: ...
    @property
    def parameters(self) -> dict[str, dict[str, object]]: ...
    @property
    def correlations(self) -> dict[str, float]: ...
    @property
    def trade_offs(self) -> dict[str, float]: ...
    @property
    def search_rms(self) -> float: ...
    @property
    def measurements(self) -> int: ...
    @property
    def beta_eq8(self) -> Optional[float]: ...
    @property
    def objective(self) -> Objective: ...
    @property
    def amplitude(self) -> Optional[float]: ...
    @property
    def chi2_weighted(self) -> Optional[float]: ...
    @property
    def adequacy(self) -> Optional[dict[str, object]]: ...
    @property
    def information(self) -> Optional[dict[str, Optional[float]]]: ...
    @property
    def rank(self) -> Optional[dict[str, float]]: ...
    @property
    def cross_validation(self) -> Optional[dict[str, float]]: ...
    @property
    def graphics(self) -> Optional[dict[str, float]]: ...
    def predict(
        self, theta_i: Array, phi_i: Array, theta_v: Array, phi_v: Array, radiance: bool = False
    ) -> Array: ...
    def to_json(self) -> str: ...

class FittedModel:
    @staticmethod
    def from_file(path: str, select: Optional[str] = None) -> FittedModel: ...
    @staticmethod
    def from_material(path: str, select: Optional[str] = None) -> list[FittedModel]: ...
    @staticmethod
    def from_params(
        model: Model, params: Mapping[str, float], amplitude: float = 1.0, data_scale: float = 1.0
    ) -> FittedModel: ...
    @staticmethod
    def from_fit(fit: FitResult) -> FittedModel: ...
    @property
    def label(self) -> str: ...
    @property
    def model(self) -> str: ...
    @property
    def data_scale(self) -> float: ...
    @property
    def eq8(self) -> Optional[dict[str, Union[str, float]]]: ...
    def radiance(self, theta_i: Array, theta_s: Array, phi_s: Array) -> Array: ...
    def albedo(self, theta_v: Array, tolerance: float = 1e-6) -> tuple[Array, Array]: ...

def render(
    models: list[FittedModel],
    size: int = 256,
    light_polar: Optional[float] = None,
    light_azimuth: Optional[float] = None,
    environment: Optional[float] = None,
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.uint8]]: ...
def fit(
    measurements: Measurements,
    model: Model = "exp",
    grid: Grid = None,
    refine: bool = True,
    uncertainty: Uncertainty = "both",
    threads: Optional[int] = None,
    objective: Objective = "free",
    resamples: int = 200,
    seed: int = 0,
    precision: Precision = "f64",
    noise: Noise = "given",
    noise_floor: float = 1.0,
) -> FitResult: ...
def compare(
    measurements: Measurements,
    models: Optional[Sequence[Model]] = None,
    grid: Grid = None,
    refine: bool = True,
    uncertainty: Uncertainty = "both",
    threads: Optional[int] = None,
    objective: Objective = "free",
    resamples: int = 200,
    seed: int = 0,
    folds: int = 5,
    precision: Precision = "f64",
    noise: Noise = "given",
    noise_floor: float = 1.0,
) -> list[FitResult]: ...
def fit_joint(
    measurements: Sequence[Measurements],
    model: LayeredModel = "exp2",
    grid: Grid = None,
    uncertainty: Uncertainty = "both",
    threads: Optional[int] = None,
    resamples: int = 200,
    seed: int = 0,
    precision: Precision = "f64",
    noise: Noise = "given",
    noise_floor: float = 1.0,
    folds: int = 5,
) -> dict[str, Any]: ...
def fit_batch(
    geometry: npt.NDArray[np.float64],
    values: npt.NDArray[np.float64],
    model: LayeredModel = "exp",
    grid: Grid = None,
    threads: Optional[int] = None,
    quantity: Quantity = "brdf",
    refine: bool = True,
    uncertainty: Uncertainty = "both",
    objective: Objective = "free",
    precision: Precision = "f64",
    noise: Noise = "given",
    noise_floor: float = 1.0,
) -> dict[str, Array]: ...
