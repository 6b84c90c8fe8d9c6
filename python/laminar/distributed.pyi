from typing import Any, Mapping, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

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
