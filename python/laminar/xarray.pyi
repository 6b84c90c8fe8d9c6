from typing import Any, Literal, Mapping, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

GEOMETRY: tuple[str, str, str, str]

def geometry_of(data: Any, dim: str) -> npt.NDArray[np.float64]: ...
def fit(
    data: Any,
    dim: str = "measurement",
    model: Literal["exp", "gauss", "rh-exp", "rh-gauss"] = "exp",
    grid: Optional[Mapping[str, Union[str, Sequence[float]]]] = None,
    quantity: Literal["brdf", "radiance"] = "brdf",
    refine: bool = True,
    uncertainty: Literal["profile", "jacobian", "both", "off"] = "both",
    objective: Literal["free", "paper"] = "free",
) -> Any: ...
