from typing import Any, Literal, Mapping, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

from ._laminar import LayeredModel, Objective, Quantity, Uncertainty

GEOMETRY: tuple[str, str, str, str]

def geometry_of(data: Any, dim: str) -> npt.NDArray[np.float64]: ...
def fit(
    data: Any,
    dim: str = "measurement",
    model: LayeredModel = "exp",
    grid: Optional[Mapping[str, Union[str, Sequence[float]]]] = None,
    quantity: Quantity = "brdf",
    refine: bool = True,
    uncertainty: Uncertainty = "both",
    objective: Objective = "free",
    sets_per_task: Union[int, Literal["auto"], None] = "auto",
) -> Any: ...
