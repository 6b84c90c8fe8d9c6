"""Scale-out: a 64 × 64 × 198 × 3 synthetic cube fitted on a Dask
LocalCluster (2 workers, 1 thread each, 127.0.0.1, no dashboard) equals the
single-process batch fit exactly."""

import os
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import laminar_brdf as laminar

if os.environ.get("LAMINAR_REQUIRE_DASK") == "1":
    import dask.distributed  # noqa: F401  (CI requires the test to run)
else:
    pytest.importorskip("dask.distributed")

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "examples"))
from btf_cube import cube  # noqa: E402


def test_local_cluster_equals_one_process():
    from dask.distributed import Client, LocalCluster

    from laminar_brdf.distributed import fit_batch_dask

    g, values = cube(64, 64, k=198, channels=3)
    pixels = values.shape[0] * values.shape[1]
    start = time.perf_counter()
    # The grid search alone (refinement costs several times the search;
    # it is compared on a slice below).
    off = {"refine": False, "uncertainty": "off"}
    alone = [laminar.fit_batch(g, v, "exp", quantity="radiance", **off) for v in values]
    single = time.perf_counter() - start
    with LocalCluster(n_workers=2, threads_per_worker=1, host="127.0.0.1", dashboard_address=None) as cluster:
        with Client(cluster) as client:
            start = time.perf_counter()
            spread = [fit_batch_dask(client, g, v, "exp", quantity="radiance", block=512, **off) for v in values]
            elapsed = time.perf_counter() - start
            # Refined, with intervals: the same on the cluster as in one process.
            part = values[0][:96]
            refined = fit_batch_dask(client, g, part, "exp", quantity="radiance", block=32)
            assert np.array_equal(
                refined.view(np.float64), laminar.fit_batch(g, part, "exp", quantity="radiance").view(np.float64),
                equal_nan=True,
            )
            assert np.all(refined["rms"] <= refined["rms_grid"])
    print(
        f"\n{pixels} pixel fits: one process (fit_batch, 2 threads) {pixels / single:.0f} pixels/s; "
        f"Dask LocalCluster (2 workers × 1 thread) {pixels / elapsed:.0f} pixels/s"
    )
    for a, b in zip(alone, spread):
        assert a.shape == (64 * 64,)
        for field in a.dtype.names:
            assert np.array_equal(a[field], b[field], equal_nan=True), field
    # The maps vary as the cube was made: σ/T grows along x.
    slope = spread[0]["slope"].reshape(64, 64)
    assert slope[:, -8:].mean() > slope[:, :8].mean() + 1.0
