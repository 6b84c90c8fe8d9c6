"""A BTF-sized job from Zarr to Zarr: a synthetic texture of SIZE × SIZE
texels × 198 directions × 3 channels (float32; 256 × 256 is 156 MB) is
written to a Zarr store, fitted lazily by laminar.xarray.fit on a Dask
cluster with a progress bar, and the result written to another store.

    python examples/btf_zarr.py                         # 256 × 256, LocalCluster 2 × 1
    python examples/btf_zarr.py --size 64 --search-only
    python examples/btf_zarr.py --scheduler tcp://HOST:8786 --out /shared/fits.zarr
    python examples/btf_zarr.py --measure --repeat 2    # the throughput table (CHANGELOG.md)

The input is stored in chunks of 3,072 sets (--rows texel rows), made
chunk by chunk, so no process holds it whole; the fit merges consecutive
chunks into tasks of a few seconds of fits (laminar.xarray.fit's
sets_per_task). --measure times fit_batch in one process (2 threads, the
texture in memory) and LocalClusters of 1 and 2 workers × 1 thread (store
to store), search only and with the defaults, on the same data, and prints
a Markdown table.
"""

import argparse
import tempfile
import time
from pathlib import Path

import dask
import dask.array as da
import numpy as np
import xarray as xr
from dask.distributed import Client, LocalCluster, progress

import laminar_brdf as laminar
import laminar_brdf.xarray
from btf_cube import geometry

K = 198
CHANNELS = ("red", "green", "blue")


def texels(block, block_info=None):
    """Rows y0..y1 of the texture: the exp model at parameters that vary
    smoothly over the texture, per channel, plus seeded noise."""
    (y0, y1), (x0, x1), _, _ = block_info[None]["array-location"]
    size = block_info[None]["shape"][1]
    g = geometry(K)
    paper = np.array([laminar.paper_angles(*row) for row in g])
    y, x = np.mgrid[y0:y1, x0:x1]
    u, v = (x + 0.5) / size, (y + 0.5) / size
    out = np.empty((y1 - y0, x1 - x0, len(CHANNELS), K), dtype=np.float32)
    rng = np.random.default_rng(y0)
    for c in range(len(CHANNELS)):
        params = [
            0.4 + 2.8 * u,
            0.15 + 0.6 * v,
            1.32 + 0.04 * c + 0.08 * u * v,
            0.1 + 0.7 * (1 - v) * (0.5 + 0.5 * np.cos(3 * u + c)),
        ]
        total = laminar.evaluate("exp", paper[:, 0], paper[:, 1], paper[:, 2], *(p[..., None] for p in params))["total"]
        total /= total.max(axis=-1, keepdims=True)
        out[:, :, c, :] = total + 0.01 * rng.standard_normal(total.shape)
    return out


def write_input(path, size, rows):
    g = geometry(K)
    lazy = da.map_blocks(
        texels,
        da.zeros((size, size, len(CHANNELS), K), chunks=(rows, size, len(CHANNELS), K), dtype=np.float32),
        dtype=np.float32,
    )
    coords = {
        "y": np.arange(size),
        "x": np.arange(size),
        "channel": np.array(CHANNELS, dtype=object),
        **{name: ("measurement", g[:, i]) for i, name in enumerate(laminar.xarray.GEOMETRY)},
    }
    data = xr.DataArray(lazy, dims=("y", "x", "channel", "measurement"), coords=coords, name="radiance")
    data.to_dataset().to_zarr(str(path), mode="w", consolidated=False)


def fit_store(client, source, out, options):
    """Fits the texture in the store ``source`` into the store ``out`` on
    ``client``'s cluster, with a progress bar of the tasks done."""
    data = xr.open_zarr(str(source), consolidated=False)["radiance"]
    fits = laminar.xarray.fit(data, model="exp", quantity="radiance", **options)
    future = client.compute(fits.to_zarr(str(out), mode="w", compute=False, consolidated=False))
    progress(future)
    future.result()
    print()


def cluster(workers):
    return LocalCluster(n_workers=workers, threads_per_worker=1, host="127.0.0.1", dashboard_address=None)


def fastest(repeat, job):
    """The shortest wall time, in seconds, of ``repeat`` calls ``job(run)``."""
    times = []
    for run in range(repeat):
        start = time.perf_counter()
        job(run)
        times.append(time.perf_counter() - start)
    return min(times)


def measure(source, scratch, size, repeat):
    """The throughput table: the fastest of ``repeat`` runs of each job, the
    one process's in memory (no reading or writing), the clusters' from
    store to store (graph, metadata, reads, fits and writes)."""
    sets = size * size * len(CHANNELS)
    data = xr.open_zarr(str(source), consolidated=False)["radiance"].load()
    rows = []
    for label, options in [("search only", {"refine": False, "uncertainty": "off"}), ("defaults", {})]:
        alone = fastest(repeat, lambda run: laminar.xarray.fit(data, model="exp", quantity="radiance", **options))
        speeds = [sets / alone]
        for workers in (1, 2):
            with cluster(workers) as c, Client(c) as client:
                out = Path(scratch) / f"fits-{workers}"
                speeds.append(sets / fastest(repeat, lambda run: fit_store(client, source, f"{out}-{run}.zarr", options)))
        rows.append((label, speeds))
    print(f"\n{sets} fits ({size} × {size} texels × 3 channels, K = {K}), sets/s, fastest of {repeat}:\n")
    print("| analysis | fit_batch, one process, 2 threads | LocalCluster 1 × 1 | LocalCluster 2 × 1 | 2 × 1 / one process |")
    print("|---|---|---|---|---|")
    for label, (one, w1, w2) in rows:
        print(f"| {label} | {one:,.0f} | {w1:,.0f} | {w2:,.0f} | {w2 / one:.2f} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--size", type=int, default=256, help="texels per side (default 256)")
    ap.add_argument("--scheduler", help="address of a running Dask scheduler (default: a LocalCluster, 2 × 1)")
    ap.add_argument("--out", help="the result's Zarr store (default: a temporary directory)")
    ap.add_argument("--search-only", action="store_true", help="the grid search alone (no refinement, no intervals)")
    ap.add_argument("--measure", action="store_true", help="print the throughput table instead")
    ap.add_argument("--repeat", type=int, default=1, help="with --measure: runs of each job, the fastest kept (default 1)")
    ap.add_argument("--rows", type=int, help="texel rows per stored chunk (default: 1024 / SIZE, at least 1)")
    args = ap.parse_args()
    if args.repeat < 1:
        ap.error(f"--repeat {args.repeat}: at least 1 run")
    with tempfile.TemporaryDirectory() as scratch:
        source = Path(scratch) / "texture.zarr"
        rows = args.rows or max(1, 1024 // args.size)  # 3,072 sets per chunk
        with dask.config.set(scheduler="threads"):
            write_input(source, args.size, rows)
        if args.measure:
            return measure(source, scratch, args.size, args.repeat)
        options = {"refine": False, "uncertainty": "off"} if args.search_only else {}
        out = Path(args.out) if args.out else Path(scratch) / "fits.zarr"
        client = Client(args.scheduler) if args.scheduler else Client(cluster(2))
        with client:
            start = time.perf_counter()
            fit_store(client, source, out, options)
            elapsed = time.perf_counter() - start
        fits = xr.open_zarr(str(out), consolidated=False)
        sets = args.size * args.size * len(CHANNELS)
        print(f"{sets} fits in {elapsed:.1f} s ({sets / elapsed:,.0f} sets/s) → {out}")
        slope = fits["slope"].sel(channel="red").values
        print(f"red σ/T map: {slope.shape}, min {slope.min():.2f}, max {slope.max():.2f} (true 0.4 … 3.2 along x)")


if __name__ == "__main__":
    main()
