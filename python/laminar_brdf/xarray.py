"""Fits of labelled arrays: an ``xarray.DataArray`` with a measurement
dimension whose coordinates are the geometry, every other dimension kept
(texels ``y``, ``x``, ``channel``, …). Lazy when the data are dask-backed
(then :func:`laminar.distributed.fit_dask` does the work, and ``to_zarr``
writes the result); numpy-backed data are fitted at once by
:func:`laminar.fit_batch`.
"""

from __future__ import annotations

import numpy as np

import laminar_brdf as laminar
from laminar_brdf.distributed import _checked, _dataset, _options, _typed, fields, fit_dask

#: The geometry's coordinates along the measurement dimension (radians,
#: lab frame).
GEOMETRY = ("theta_i", "phi_i", "theta_v", "phi_v")


def geometry_of(data, dim):
    """The K × 4 geometry of ``data`` from its coordinates along ``dim``."""
    columns = []
    for name in GEOMETRY:
        if name not in data.coords:
            raise ValueError(
                f"data: no coordinate {name!r}; the geometry is given as coordinates "
                f"{', '.join(GEOMETRY)} (radians) along {dim!r}"
            )
        coord = data.coords[name]
        if coord.dims != (dim,):
            raise ValueError(f"data: coordinate {name!r} has dimensions {coord.dims}; it must lie along ({dim!r},)")
        columns.append(np.asarray(coord.values, dtype=np.float64))
    return np.column_stack(columns)


def fit(
    data,
    dim="measurement",
    model="exp",
    grid=None,
    quantity="brdf",
    refine=True,
    uncertainty="both",
    objective="free",
    sets_per_task="auto",
):
    """Fits ``model`` to every set of ``data`` along ``dim`` (the
    measurements, with coordinates ``theta_i, phi_i, theta_v, phi_v``), as
    :func:`laminar.fit_batch` does with the same options.

    Returns an ``xarray.Dataset`` of the output fields
    (:func:`laminar.distributed.fields` of ``model``), each with ``data``'s other
    dimensions, in their order, and their coordinates. Lazy when ``data`` is
    dask-backed (chunks along ``dim`` are merged into one); a value that is
    not finite then raises when its chunk runs, naming the set by its index
    in row-major order over the other dimensions (numpy-backed data name
    its coordinates at once). ``sets_per_task`` as in
    :func:`laminar.distributed.fit_dask`.
    """
    import dask.array as da
    import xarray as xr

    if not isinstance(data, xr.DataArray):
        raise ValueError(f"data: {type(data).__name__}; an xarray.DataArray is needed")
    if dim not in data.dims:
        raise ValueError(f"dim: {dim!r} is not a dimension of data (dimensions {data.dims})")
    geometry = geometry_of(data, dim)
    others = [d for d in data.dims if d != dim]
    data = data.transpose(*others, dim)
    shape = tuple(data.sizes[d] for d in others)
    sets = int(np.prod(shape)) if shape else 1
    flat = data.data.reshape(sets, geometry.shape[0])
    coords = {name: c for name, c in data.coords.items() if dim not in c.dims}
    options = _options(grid, quantity, refine, uncertainty, objective)
    if isinstance(flat, da.Array):
        fitted = fit_dask(geometry, flat, model, dim="set", sets_per_task=sets_per_task, **options)
        columns = {name: fitted[name].data.reshape(shape) for name in fields(model)}
    else:
        _checked(geometry, flat, model, options)
        flat = np.ascontiguousarray(flat, dtype=np.float64)
        bad = ~np.isfinite(flat)
        if bad.any():
            row, column = np.argwhere(bad)[0]
            where = ", ".join(f"{d}={i}" for d, i in zip(others, np.unravel_index(row, shape)))
            raise ValueError(
                f"data: the set at {where or 'the only set'} holds {flat[row, column]} at {dim}={column}; "
                "every value must be a finite number"
            )
        out = laminar.fit_batch(geometry, flat, model, **options)
        columns = {name: out[name].reshape(shape) for name in fields(model)}
    # (fit_dask's columns are typed already: dask's astype to their own dtype
    # returns them as they are.)
    variables = {name: xr.Variable(others, *_typed(name, column)) for name, column in columns.items()}
    return _dataset(variables, coords, model, objective, quantity)
