"""Batch fits of chunked arrays with Dask, lazily: from any Dask array (a
Zarr store, an HDF5 file, a stack of images) to an ``xarray.Dataset`` of
plain float arrays, one per output field, which the caller computes or
stores (``to_zarr``) where the data live.

Each chunk of sets is one :func:`laminar.fit_batch` call (``threads=1``)
on a worker; the geometry is one key of the graph, so it reaches each
worker once. Nothing is gathered into the client. Any Dask scheduler
runs it: a ``distributed`` cluster (local or on other machines), the
threaded scheduler, or the synchronous one. Dask and xarray are optional
dependencies (``pip install "laminar-brdf[dask]"``).
"""

from __future__ import annotations

import numpy as np

import laminar_brdf as laminar

#: The fields of the result for the tied models, in
#: :data:`laminar.BATCH_COLUMNS` order (:func:`fields` gives any layered
#: model's).
FIELDS = tuple(laminar.BATCH_COLUMNS)


def fields(model):
    """The fields of the result for ``model`` (a layered model), in order:
    :data:`FIELDS`, and for the untied models (``exp2``, ``gauss2``) σ′/T′'s
    (``sub_slope``, …) after σ/T's (:func:`laminar.batch_fields`)."""
    return tuple(name for name, _ in laminar.batch_fields(model))


#: Rows per chunk when :func:`fit_dask` is given a numpy array.
DEFAULT_CHUNK = 4096

#: What ``sets_per_task="auto"`` aims at: seconds of fits per task on one
#: core. A task has a fixed cost besides its fits (one Zarr write and one
#: task of the scheduler per output field and chunk, 1–3 ms each,
#: docs/python.md), so tasks of a few
#: seconds keep it to a few percent, while leaving enough tasks to share
#: among the workers.
TASK_SECONDS = 3.0

#: One core's seconds per set and measurement of each stage of each
#: objective, exp model, its default grid (measured on the reference
#: machine with ``fit_batch(threads=1)`` on a synthetic texture,
#: CHANGELOG.md): the grid search, the refinement, the profile intervals.
#: The Jacobian costs next to nothing.
STAGE_SECONDS = {
    "free": {"search": 1.1e-6, "refine": 3.3e-6, "profile": 4.8e-6},
    "paper": {"search": 2.3e-6, "refine": 55e-6, "profile": 67e-6},
}


def _is_flags(name):
    return name.endswith("_flags")


def _check_finite(block, offset):
    bad = ~np.isfinite(block)
    if bad.any():
        row, column = np.argwhere(bad)[0]
        raise ValueError(
            f"values: set {offset + row} holds {block[row, column]} at measurement {column}; "
            "every value must be a finite number"
        )


def _fit_chunk(block, geometry, model, options, block_info=None):
    """One chunk of sets (n × K) → its n × len(fields(model)) results."""
    offset = block_info[0]["array-location"][0][0] if block_info else 0
    block = np.ascontiguousarray(block, dtype=np.float64)
    _check_finite(block, offset)
    out = laminar.fit_batch(geometry, block, model, threads=1, **options)
    return np.column_stack([out[name] for name in out.dtype.names])


def _seconds_per_set(k, options):
    """The estimated seconds of one core per set of ``k`` measurements
    (:data:`STAGE_SECONDS`)."""
    stages = STAGE_SECONDS[options["objective"]]
    refine = stages["refine"] if options["refine"] else 0.0
    profile = stages["profile"] if options["uncertainty"] in ("profile", "both", "bootstrap") else 0.0
    return max(k, 1) * (stages["search"] + refine + profile)


def _chunks_per_task(chunks, k, options, sets_per_task):
    """How many consecutive chunks of sets (``chunks``, their sizes) one task
    fits: as many as hold at most ``sets_per_task`` sets (at least one), or
    with ``"auto"`` about :data:`TASK_SECONDS` of fits; ``None`` keeps each
    chunk a task."""
    if sets_per_task is None:
        return 1
    if isinstance(sets_per_task, str):
        if sets_per_task != "auto":
            raise ValueError(f"sets_per_task: {sets_per_task!r}; a number of sets, 'auto' or None is needed")
        sets_per_task = TASK_SECONDS / _seconds_per_set(k, options)
    elif isinstance(sets_per_task, bool) or not isinstance(sets_per_task, (int, np.integer)) or sets_per_task < 1:
        raise ValueError(f"sets_per_task: {sets_per_task!r}; a number of sets ≥ 1, 'auto' or None is needed")
    largest = max(max(chunks, default=1), 1)
    return max(1, int(sets_per_task // largest))


def _merged(chunks, per_task):
    """``chunks`` merged ``per_task`` at a time (the last group may be
    smaller), so that every boundary of the result is one of the input's."""
    return tuple(sum(chunks[i : i + per_task]) for i in range(0, len(chunks), per_task))


def _options(grid, quantity, refine, uncertainty, objective):
    """The options every fit_batch call of one job takes."""
    return {"grid": grid, "quantity": quantity, "refine": refine, "uncertainty": uncertainty, "objective": objective}


#: Each field's dtype (:func:`laminar.batch_fields`, the library's kinds), of
#: every layered model (of :data:`laminar.MODELS`).
DTYPES = {
    name: np.dtype(dtype)
    for model, described in laminar.MODELS.items()
    if described["correlation"] is not None
    for name, dtype in laminar.batch_fields(model)
}


def _typed(name, column):
    """Field ``name``'s column (numpy or dask) in its output dtype
    (:data:`DTYPES`), with its attributes: a ``*_flags`` field has
    :func:`flag_attrs` (the integer fields are never NaN for a layered
    model)."""
    dtype = DTYPES[name]
    attrs = flag_attrs() if _is_flags(name) else {}
    if dtype == np.float64:
        return column, attrs
    return column.astype(dtype), attrs


def _dataset(variables, coords, model, objective, quantity):
    """The result's Dataset, saying how it was made."""
    import xarray as xr

    attrs = {"model": model, "objective": objective, "quantity": quantity, "fitted_by": "laminar.fit_batch"}
    return xr.Dataset(variables, coords=coords, attrs=attrs)


def _checked(geometry, values, model, options):
    """The geometry as a K × 4 float array, after checking ``values``' shape
    and dtype against it and the options against the engine (a fit of no
    sets)."""
    geometry = np.ascontiguousarray(geometry, dtype=np.float64)
    if geometry.ndim != 2 or geometry.shape[1] != 4:
        raise ValueError(
            f"geometry: shape {geometry.shape}; (K, 4) lab-frame angles theta_i, phi_i, theta_v, phi_v are needed"
        )
    if values.ndim != 2:
        raise ValueError(f"values: shape {values.shape}; an N × K array (sets × measurements) is needed")
    dtype = np.dtype(values.dtype)
    if not (np.issubdtype(dtype, np.floating) or np.issubdtype(dtype, np.integer)):
        raise ValueError(f"values: dtype {dtype}; real numbers (a float or integer dtype) are needed")
    if values.shape[1] != geometry.shape[0]:
        raise ValueError(
            f"values: {values.shape[1]} measurements per set but the geometry has {geometry.shape[0]} rows"
        )
    laminar.fit_batch(geometry, np.empty((0, geometry.shape[0])), model, threads=1, **options)
    return geometry


def flag_attrs():
    """CF-style attributes of a ``*_flags`` variable: which bit says what."""
    names = sorted(laminar.FLAG_BITS, key=laminar.FLAG_BITS.get)
    return {
        "flag_masks": [laminar.FLAG_BITS[n] for n in names],
        "flag_meanings": " ".join(names),
        "comment": "sum of the bits of the flags that apply; 0 = none (see laminar.FLAG_BITS)",
    }


def fit_dask(
    geometry,
    values,
    model="exp",
    grid=None,
    quantity="brdf",
    refine=True,
    uncertainty="both",
    objective="free",
    dim="set",
    sets_per_task="auto",
):
    """Fits every row of ``values`` (a ``dask.array`` of N sets × K
    measurements, chunked along N; a numpy array is chunked by
    :data:`DEFAULT_CHUNK` rows) on ``geometry`` (K × 4 lab-frame angles,
    radians) as :func:`laminar.fit_batch` does, with the same options.

    Each task fits consecutive chunks of sets together: as many as hold at
    most ``sets_per_task`` sets (at least one chunk), or by default
    (``"auto"``) about :data:`TASK_SECONDS` of one core's fits, estimated
    from K and the analysis (:data:`STAGE_SECONDS`); ``None`` makes each
    chunk a task. Chunks are merged, never split, so the result's chunks
    along ``dim`` are the merged ones and each boundary is one of the
    input's.

    Returns at once a lazy ``xarray.Dataset`` along ``dim``: one variable
    per field of :func:`fields` (``model``) (float64; ``measurements`` int32; the
    ``*_flags`` uint8, with ``flag_masks`` and ``flag_meanings``
    attributes). Nothing runs until the caller computes it or stores it
    (``to_zarr``). Chunks along K are merged into one; each chunk of sets is
    one task, whose keys are named ``laminar-brdf-fit``.

    Errors found without computing (shapes, dtype, options) raise
    ``ValueError`` here; a value that is not finite raises it when its chunk
    runs, naming the set's index in ``values``.
    """
    import dask
    import dask.array as da
    import xarray as xr

    if not isinstance(values, da.Array):
        values = da.from_array(np.asarray(values), chunks=(DEFAULT_CHUNK, -1))
    options = _options(grid, quantity, refine, uncertainty, objective)
    geometry = _checked(geometry, values, model, options)
    per_task = _chunks_per_task(values.chunks[0], geometry.shape[0], options, sets_per_task)
    values = values.rechunk({0: _merged(values.chunks[0], per_task), 1: -1})
    shared = dask.delayed(geometry, pure=True)
    columns = da.map_blocks(
        _fit_chunk,
        values,
        shared,
        model,
        options,
        dtype=np.float64,
        chunks=(values.chunks[0], (len(fields(model)),)),
        meta=np.empty((0, 0), dtype=np.float64),
        token="laminar-brdf-fit",
    )
    variables = {name: xr.Variable((dim,), *_typed(name, columns[:, i])) for i, name in enumerate(fields(model))}
    return _dataset(variables, None, model, objective, quantity)


def to_records(dataset):
    """The computed Dataset of :func:`fit_dask` as the structured array
    :func:`laminar.fit_batch` returns (every field as float64; the fields
    of the Dataset's ``model`` attribute)."""
    n = dataset.sizes[next(iter(dataset.sizes))] if dataset.sizes else 0
    dtype = laminar.batch_dtype(dataset.attrs["model"])
    out = np.empty(n, dtype=dtype)
    for name in dtype.names:
        out[name] = np.asarray(dataset[name].values, dtype=np.float64)
    return out


def fit_batch_dask(
    client, geometry, values, model="exp", grid=None, quantity="brdf", block=512, refine=True, uncertainty="both"
):
    """:func:`fit_dask` of a numpy ``values`` in chunks of ``block`` rows,
    computed on the ``distributed.Client`` ``client`` and returned as
    :func:`laminar.fit_batch`'s structured array. Kept for the callers of
    the first version; it holds the whole input and output in the client,
    which :func:`fit_dask` does not."""
    import dask.array as da

    if block < 1:
        raise ValueError(f"block: {block}; at least 1 row per task")
    values = np.asarray(values)
    if values.ndim != 2:
        raise ValueError(f"values: shape {values.shape}; an N × K array is needed")
    chunked = da.from_array(values, chunks=(block, -1))
    dataset = fit_dask(
        geometry, chunked, model, grid=grid, quantity=quantity, refine=refine, uncertainty=uncertainty, sets_per_task=None
    )
    return to_records(client.compute(dataset).result())
