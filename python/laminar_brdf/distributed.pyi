from typing import Any, Literal, Mapping, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

from ._laminar import LayeredModel, Objective, Quantity, Uncertainty

FIELDS: tuple[str, ...]

def fields(model: LayeredModel = "exp") -> tuple[str, ...]: ...
DTYPES: dict[str, np.dtype[Any]]
DEFAULT_CHUNK: int
TASK_SECONDS: float
STAGE_SECONDS: dict[str, dict[str, float]]

def flag_attrs() -> dict[str, Any]: ...
def fit_dask(
    geometry: npt.ArrayLike,
    values: Any,
    model: LayeredModel = "exp",
    grid: Optional[Mapping[str, Union[str, Sequence[float]]]] = None,
    quantity: Quantity = "brdf",
    refine: bool = True,
    uncertainty: Uncertainty = "both",
    objective: Objective = "free",
    dim: str = "set",
    sets_per_task: Union[int, Literal["auto"], None] = "auto",
) -> Any: ...
def to_records(dataset: Any) -> npt.NDArray[np.void]: ...
def fit_batch_dask(
    client: Any,
    geometry: npt.ArrayLike,
    values: npt.ArrayLike,
    model: LayeredModel = "exp",
    grid: Optional[Mapping[str, Union[str, Sequence[float]]]] = None,
    quantity: Quantity = "brdf",
    block: int = 512,
    refine: bool = True,
    uncertainty: Uncertainty = "both",
) -> npt.NDArray[np.void]: ...
