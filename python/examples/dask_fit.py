"""Fit every pixel of a synthetic BTF-like cube on a Dask cluster and compare
with the single-process batch fit.

    python examples/dask_fit.py                       # a LocalCluster, 2 workers × 1 thread
    python examples/dask_fit.py --scheduler tcp://host:8786   # a running cluster

Prints pixels/s for both and checks that the parameter maps are identical.
"""

import argparse
import time

import numpy as np
from dask.distributed import Client, LocalCluster

import laminar_brdf as laminar
from laminar_brdf.distributed import fit_batch_dask
from btf_cube import cube


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scheduler", help="address of a running Dask scheduler (default: a LocalCluster)")
    ap.add_argument("--size", type=int, default=64, help="pixels per side (default 64)")
    ap.add_argument("--block", type=int, default=512, help="pixels per task (default 512)")
    args = ap.parse_args()
    g, values = cube(args.size, args.size)
    pixels = values.shape[0] * values.shape[1]
    start = time.perf_counter()
    alone = [laminar.fit_batch(g, v, "exp", quantity="radiance") for v in values]
    single = time.perf_counter() - start
    print(f"fit_batch, one process: {pixels} pixel fits in {single:.2f} s, {pixels / single:.0f} pixels/s")
    if args.scheduler:
        client = Client(args.scheduler)
    else:
        cluster = LocalCluster(n_workers=2, threads_per_worker=1, host="127.0.0.1", dashboard_address=None)
        client = Client(cluster)
    with client:
        start = time.perf_counter()
        spread = [fit_batch_dask(client, g, v, "exp", quantity="radiance", block=args.block) for v in values]
        dask_time = time.perf_counter() - start
    print(f"Dask: {pixels} pixel fits in {dask_time:.2f} s, {pixels / dask_time:.0f} pixels/s")
    same = all(np.array_equal(a[f], b[f], equal_nan=True) for a, b in zip(alone, spread) for f in a.dtype.names)
    print("parameter maps identical:", same)
    slope = spread[0]["slope"].reshape(args.size, args.size)
    print(f"channel 0 sigma/T map: min {slope.min():.2f}, max {slope.max():.2f}")
    raise SystemExit(0 if same else 1)


if __name__ == "__main__":
    main()
