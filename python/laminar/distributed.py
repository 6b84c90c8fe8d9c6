"""Batch fits spread over a Dask cluster.

Each task fits one block of rows with :func:`laminar.fit_batch` in one
worker thread (``threads=1``); the blocks are gathered in order, so the
result is the same array :func:`laminar.fit_batch` gives in one process.
Dask is an optional dependency (``pip install "laminar[dask]"``).
"""

from __future__ import annotations

import numpy as np

import laminar


def _fit_block(geometry, block, model, grid, quantity, analysis):
    refine, uncertainty = analysis
    return laminar.fit_batch(
        geometry, block, model, grid=grid, threads=1, quantity=quantity, refine=refine, uncertainty=uncertainty
    )


def fit_batch_dask(
    client, geometry, values, model="exp", grid=None, quantity="brdf", block=512, refine=True, uncertainty="both"
):
    """Fits every row of ``values`` (N × K) on ``geometry`` (K × 4) as
    :func:`laminar.fit_batch` does (``refine`` and ``uncertainty`` as
    there), in blocks of ``block`` rows, one task per
    block on the workers of the ``distributed.Client`` ``client``. The
    geometry is scattered once to every worker (under a fresh key, so that
    calls in a row do not share, and release, one another's copy)."""
    values = np.ascontiguousarray(values, dtype=np.float64)
    if values.ndim != 2:
        raise ValueError(f"values: shape {values.shape}; an N × K array is needed")
    if block < 1:
        raise ValueError(f"block: {block}; at least 1 row per task")
    shared = client.scatter(np.ascontiguousarray(geometry, dtype=np.float64), broadcast=True, hash=False)
    futures = [
        client.submit(
            _fit_block, shared, values[i : i + block], model, grid, quantity, (refine, uncertainty), pure=False
        )
        for i in range(0, values.shape[0], block)
    ]
    parts = client.gather(futures)
    return np.concatenate(parts) if parts else np.empty(0, dtype=laminar.BATCH_DTYPE)
