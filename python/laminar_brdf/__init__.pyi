"""Type stubs of the laminar package."""

from typing import Optional

import numpy as np
import numpy.typing as npt

from ._laminar import BATCH_COLUMNS as BATCH_COLUMNS
from ._laminar import BATCH_DTYPES as BATCH_DTYPES
from ._laminar import batch_fields as batch_fields
from ._laminar import FLAG_BITS as FLAG_BITS
from ._laminar import GRID_AXES as GRID_AXES
from ._laminar import MODELS as MODELS
from ._laminar import FitResult as FitResult
from ._laminar import compare as compare
from ._laminar import fit_joint as fit_joint
from ._laminar import fit as fit
from ._laminar import FittedModel as FittedModel
from ._laminar import render as render
from ._laminar import AngleUnit, Grid, LayeredModel, Model, Noise, Objective, Precision, Quantity, Uncertainty
from ._laminar import Measurements as Measurements
from ._laminar import paper_angles as paper_angles
from ._laminar import simd_path as simd_path

BATCH_DTYPE: np.dtype[np.void]

def batch_dtype(model: LayeredModel = "exp") -> np.dtype[np.void]: ...

def evaluate(
    model: LayeredModel,
    theta_i: npt.ArrayLike,
    theta_s: npt.ArrayLike,
    phi_s: npt.ArrayLike,
    slope: npt.ArrayLike,
    beta: npt.ArrayLike,
    n: npt.ArrayLike,
    a: npt.ArrayLike,
    sub_slope: Optional[npt.ArrayLike] = None,
    precision: Precision = "f64",
) -> dict[str, npt.NDArray[np.float64]]: ...
def fit_batch(
    geometry: npt.ArrayLike,
    values: npt.ArrayLike,
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
) -> npt.NDArray[np.void]: ...
