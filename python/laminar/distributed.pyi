from typing import Any, Literal, Mapping, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

FIELDS: tuple[str, ...]
DEFAULT_CHUNK: int

def flag_attrs() -> dict[str, Any]: ...
def fit_dask(
    geometry: npt.ArrayLike,
    values: Any,
    model: Literal["exp", "gauss", "rh-exp", "rh-gauss"] = "exp",
    grid: Optional[Mapping[str, Union[str, Sequence[float]]]] = None,
    quantity: Literal["brdf", "radiance"] = "brdf",
    refine: bool = True,
    uncertainty: Literal["profile", "jacobian", "both", "off"] = "both",
    objective: Literal["free", "paper"] = "free",
    dim: str = "set",
) -> Any: ...
def to_records(dataset: Any) -> npt.NDArray[np.void]: ...
def fit_batch_dask(
    client: Any,
    geometry: npt.ArrayLike,
    values: npt.ArrayLike,
    model: str = "exp",
    grid: Optional[Mapping[str, Union[str, Sequence[float]]]] = None,
    quantity: str = "brdf",
    block: int = 512,
    refine: bool = True,
    uncertainty: str = "both",
) -> npt.NDArray[np.void]: ...
