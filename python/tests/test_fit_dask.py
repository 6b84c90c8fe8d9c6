"""Lazy fits of chunked data (laminar.distributed.fit_dask, laminar.xarray.fit):
Zarr to Zarr on a LocalCluster whose workers each have less memory than
the input, equal to laminar.fit_batch row for row in every field; the
client's memory; a worker killed mid-run; labelled cubes; bad input."""

import os
import signal
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import laminar_brdf as laminar

if os.environ.get("LAMINAR_REQUIRE_DASK") == "1":
    import dask.distributed  # noqa: F401  (CI requires these tests to run)
    import xarray  # noqa: F401
    import zarr  # noqa: F401
else:
    pytest.importorskip("dask.distributed")
    pytest.importorskip("xarray")
    pytest.importorskip("zarr")

import dask  # noqa: E402
import dask.array as da  # noqa: E402
import xarray as xr  # noqa: E402

import laminar_brdf.distributed  # noqa: E402
from laminar_brdf.distributed import FIELDS, fit_dask  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "examples"))
from btf_cube import cube  # noqa: E402

#: A small grid, so that the big store's ~200,000 fits take seconds (the
#: engine's search is the same at any grid; the defaults are compared on a
#: smaller set below).
SMALL_GRID = {"slope": "0.1:4:4:log", "n": "1.2:1.6:2", "a": "0:1:3"}
SEARCH = {"grid": SMALL_GRID, "quantity": "radiance", "refine": False, "uncertainty": "off"}
CHUNK = 4096
CHUNKS = 56
#: Each worker's memory limit, below the input's 363 MB (a worker peaks near
#: 190 MB here). Workers do not pause near it (a paused worker that cannot
#: free memory would hang the test); above 95% of it the nanny kills them.
WORKER_MEMORY = 300e6


def status(field):
    """This process's `field` of /proc/self/status, in bytes."""
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith(field + ":"):
            return int(line.split()[1]) * 1024
    raise KeyError(field)


def worker_peak():
    """The calling worker's peak resident memory, in bytes."""
    return status("VmHWM")


def synthetic_chunk(block, block_info=None):
    """Chunk i of the big input: the 64 × 64 cube's sets plus noise seeded
    by i (made chunk by chunk, so no process holds the whole input)."""
    i = block_info[None]["chunk-location"][0]
    g, values = cube(64, 64, k=198, channels=1)
    rng = np.random.default_rng(100 + i)
    return values[0] + 0.005 * rng.standard_normal(values[0].shape)


@pytest.fixture(scope="module")
def store(tmp_path_factory):
    """The big input (CHUNKS × CHUNK sets × 198, float64), written to a Zarr
    store by the threaded scheduler, and its geometry."""
    path = tmp_path_factory.mktemp("zarr") / "values.zarr"
    g, _ = cube(1, 1, k=198, channels=1)
    lazy = da.map_blocks(
        synthetic_chunk,
        da.zeros((CHUNKS * CHUNK, 198), chunks=(CHUNK, 198)),
        dtype=np.float64,
    )
    with dask.config.set(scheduler="threads"):
        lazy.to_zarr(str(path))
    return g, path


@pytest.fixture(scope="module")
def reference(store):
    """laminar.fit_batch of every chunk of the store, in one process."""
    g, path = store
    values = da.from_zarr(str(path))
    start = time.perf_counter()
    parts = [laminar.fit_batch(g, np.asarray(values[i : i + CHUNK]), "exp", **SEARCH) for i in range(0, values.shape[0], CHUNK)]
    elapsed = time.perf_counter() - start
    return np.concatenate(parts), elapsed


def assert_equal_rows(result, expected):
    for name in expected.dtype.names:
        got = np.asarray(result[name].values, dtype=np.float64)
        assert np.array_equal(got, expected[name], equal_nan=True), name


def test_zarr_to_zarr_on_workers_with_less_memory_than_the_input(store, reference, tmp_path):
    from dask.distributed import Client, LocalCluster

    g, path = store
    expected, alone = reference
    values = da.from_zarr(str(path))
    size = values.nbytes
    assert WORKER_MEMORY < size
    with dask.config.set({"distributed.worker.memory.pause": False}), LocalCluster(
        n_workers=2,
        threads_per_worker=1,
        memory_limit=WORKER_MEMORY,
        host="127.0.0.1",
        dashboard_address=None,
    ) as cluster, Client(cluster) as client:
        result = fit_dask(g, values, "exp", **SEARCH)
        assert all(isinstance(result[name].data, da.Array) for name in FIELDS)
        out = tmp_path / "fits.zarr"
        stored = result.to_zarr(str(out), compute=False)
        # The client's peak memory from here on (VmHWM reset to the
        # current resident size).
        Path("/proc/self/clear_refs").write_text("5")
        before = status("VmRSS")
        start = time.perf_counter()
        client.compute(stored).result()
        elapsed = time.perf_counter() - start
        grown = status("VmHWM") - before
        peaks = client.run(worker_peak)

        # A second run, one worker killed (SIGKILL) a third of the way in:
        # the nanny starts a new one and the lost share is recomputed.
        again = tmp_path / "again.zarr"
        future = client.compute(fit_dask(g, values, "exp", **SEARCH).to_zarr(str(again), compute=False))
        time.sleep(elapsed / 3)
        assert not future.done(), "the run ended before the kill"
        victim = sorted(client.run(os.getpid).values())[0]
        os.kill(victim, signal.SIGKILL)
        future.result()
        survivors = client.run(os.getpid)
    n = values.shape[0]
    print(
        f"\nfit_dask, {n} sets × 198 ({size / 1e6:.0f} MB), small grid, search only: "
        f"fit_batch in one process (2 threads) {n / alone:.0f} sets/s; "
        f"LocalCluster 2 workers × 1 thread ({WORKER_MEMORY / 1e6:.0f} MB each) {n / elapsed:.0f} sets/s; "
        f"client peak grew {grown / 1e6:.1f} MB; worker peaks "
        + ", ".join(f"{p / 1e6:.0f} MB" for p in peaks.values())
    )
    assert grown < size / 4, f"the client grew by {grown / 1e6:.0f} MB for a {size / 1e6:.0f} MB input"
    assert victim not in survivors.values()
    assert_equal_rows(xr.open_zarr(str(out)).load(), expected)
    assert_equal_rows(xr.open_zarr(str(again)).load(), expected)


def test_the_defaults_on_the_threaded_scheduler_equal_fit_batch():
    # Refinement and both uncertainties (every field, intervals and flags
    # included), on irregular chunks along both axes.
    g, values = cube(12, 12, k=198, channels=1)
    sets = values[0]
    lazy = da.from_array(sets, chunks=((50, 60, 34), (100, 98)))
    result = fit_dask(g, lazy, "exp", quantity="radiance")
    assert result["n_flags"].dtype == np.uint8 and result["measurements"].dtype == np.int32
    assert result["n_flags"].attrs["flag_meanings"].split()[0] == "range_edge"
    with dask.config.set(scheduler="threads"):
        computed = result.compute()
    expected = laminar.fit_batch(g, sets, "exp", quantity="radiance")
    assert_equal_rows(computed, expected)
    assert np.isfinite(computed["n_lo95"]).all() and np.isfinite(computed["amplitude"]).all()


def test_chunks_are_merged_into_tasks_of_the_size_asked():
    g, values = cube(10, 10, k=198, channels=1)
    sets = values[0]
    lazy = da.from_array(sets, chunks=(10, 198))
    search = {"quantity": "radiance", "refine": False, "uncertainty": "off"}

    def task_chunks(**kw):
        return fit_dask(g, lazy, "exp", **search, **kw)["slope"].data.chunks[0]

    assert task_chunks(sets_per_task=35) == (30, 30, 30, 10)
    assert task_chunks(sets_per_task=5) == (10,) * 10  # a chunk is never split
    assert task_chunks(sets_per_task=None) == (10,) * 10
    # "auto": about TASK_SECONDS of one core's fits per task, by the stage
    # costs: the search alone merges these 100 small sets into one task;
    # a costlier analysis takes fewer sets per task.
    assert task_chunks() == (100,)
    per_set = 198 * sum(laminar.distributed.STAGE_SECONDS["free"].values())
    many = da.zeros((5000, 198), chunks=(1, 198))  # (its chunks only: nothing is computed)
    full = fit_dask(g, many, "exp", quantity="radiance")
    assert full["slope"].data.chunks[0][0] == int(laminar.distributed.TASK_SECONDS / per_set) < 5000
    with dask.config.set(scheduler="threads"):
        computed = fit_dask(g, lazy, "exp", **search, sets_per_task=35).compute()
    assert_equal_rows(computed, laminar.fit_batch(g, sets, "exp", **search))
    for bad in (0, -3, 2.5, True, "big"):
        with pytest.raises(ValueError, match="sets_per_task"):
            fit_dask(g, lazy, "exp", sets_per_task=bad)


def labelled_cube(ny=6, nx=5, channels=3):
    g, values = cube(ny, nx, k=198, channels=channels)
    # values: channels × (y·x) × K → (y, x, channel, measurement)
    data = values.reshape(channels, ny, nx, 198).transpose(1, 2, 0, 3)
    coords = {
        "y": np.arange(ny) * 0.5,
        "x": np.arange(nx) * 0.25,
        "channel": ["red", "green", "blue"][:channels],
        **{name: ("measurement", g[:, i]) for i, name in enumerate(("theta_i", "phi_i", "theta_v", "phi_v"))},
    }
    return g, xr.DataArray(data, dims=("y", "x", "channel", "measurement"), coords=coords, attrs={"units": "1"})


def test_xarray_fit_keeps_dimensions_and_equals_fit_batch_per_texel(tmp_path):
    import laminar_brdf.xarray

    g, data = labelled_cube()
    result = laminar.xarray.fit(data, model="exp", quantity="radiance")
    assert result["slope"].dims == ("y", "x", "channel")
    assert list(result["slope"].coords["channel"].values) == ["red", "green", "blue"]
    assert np.array_equal(result["slope"].coords["x"].values, data.coords["x"].values)
    for iy in range(data.sizes["y"]):
        for c in range(data.sizes["channel"]):
            row = laminar.fit_batch(g, data.values[iy, :, c, :], "exp", quantity="radiance")
            for name in FIELDS:
                got = np.asarray(result[name].values[iy, :, c], dtype=np.float64)
                assert np.array_equal(got, row[name], equal_nan=True), (name, iy, c)

    # Dask-backed, channel-first in memory: lazy, the same numbers, stored.
    chunked = data.transpose("channel", "measurement", "y", "x").chunk({"y": 2, "measurement": 99})
    lazy = laminar.xarray.fit(chunked, model="exp", quantity="radiance")
    assert isinstance(lazy["slope"].data, da.Array)
    assert lazy["slope"].dims == ("channel", "y", "x")
    with dask.config.set(scheduler="threads"):
        lazy.to_zarr(str(tmp_path / "cube.zarr"))
    stored = xr.open_zarr(str(tmp_path / "cube.zarr")).load()
    for name in FIELDS:
        want = result[name].transpose("channel", "y", "x").values
        assert np.array_equal(stored[name].values, want, equal_nan=True), name
    assert list(stored.coords["channel"].values) == ["red", "green", "blue"]


def test_the_cli_python_and_dask_emit_one_batch_row(tmp_path):
    """`laminar fit-batch`'s CSV, `laminar.fit_batch` and the Dask/xarray
    fields: one list of fields (the CLI's file adds the key `set,model` in
    front), and the same numbers."""
    import laminar_brdf.xarray
    from conftest import GRID, GRID_ARGS, cli, geometry, radiance

    g = geometry(60)
    values = np.stack([radiance(g, slope=s, seed=i) for i, s in enumerate([0.7, 1.3])])
    (tmp_path / "g.csv").write_text(
        "theta_i,phi_i,theta_v,phi_v\n" + "".join(",".join(repr(float(x)) for x in row) + "\n" for row in g)
    )
    (tmp_path / "v.csv").write_text("".join(",".join(repr(float(x)) for x in row) + "\n" for row in values))
    out = tmp_path / "batch.csv"
    cli("fit-batch", "--geometry", tmp_path / "g.csv", "--values", tmp_path / "v.csv", "--quantity", "radiance",
        *GRID_ARGS, "--out", out)
    header, *lines = out.read_text().splitlines()
    header = header.split(",")
    assert header[:2] == ["set", "model"]
    assert header[2:] == list(laminar.BATCH_COLUMNS) == list(FIELDS)
    assert [name for name, _ in laminar.BATCH_DTYPES] == list(laminar.BATCH_COLUMNS)
    python = laminar.fit_batch(g, values, "exp", grid=GRID, quantity="radiance")
    data = xr.DataArray(values, dims=("set", "measurement"),
                        coords={n: ("measurement", g[:, i]) for i, n in enumerate(laminar.xarray.GEOMETRY)})
    dask_fields = laminar.xarray.fit(data.chunk({"set": 1}), model="exp", grid=GRID, quantity="radiance").compute()
    assert list(dask_fields.data_vars) == list(FIELDS)
    for r, line in enumerate(lines):
        cells = line.split(",")
        assert cells[:2] == [str(r), "exp"]
        for name, cell in zip(header[2:], cells[2:]):
            written = float(cell) if cell else np.nan
            assert np.array_equal(written, python[name][r], equal_nan=True), (name, cell, python[name][r])
            assert np.array_equal(float(dask_fields[name].values[r]), python[name][r], equal_nan=True), name


def test_bad_input_is_named():
    import laminar_brdf.xarray

    g, values = cube(4, 4, k=198, channels=1)
    sets = values[0]
    with pytest.raises(ValueError, match="197 measurements per set but the geometry has 198 rows"):
        fit_dask(g, da.from_array(sets[:, :197]), "exp")
    with pytest.raises(ValueError, match="dtype <U"):
        fit_dask(g, da.from_array(sets.astype(str)), "exp")
    with pytest.raises(ValueError, match="dtype complex128"):
        fit_dask(g, da.from_array(sets.astype(complex)), "exp")
    with pytest.raises(ValueError, match="model"):
        fit_dask(g, da.from_array(sets), "lambert")
    broken = sets.copy()
    broken[11, 40] = np.nan
    lazy = fit_dask(g, da.from_array(broken, chunks=(5, 198)), "exp", quantity="radiance", **{"refine": False})
    with pytest.raises(ValueError, match="set 11 holds nan at measurement 40"):
        lazy.compute(scheduler="synchronous")

    _, data = labelled_cube(3, 3, 1)
    with pytest.raises(ValueError, match="no coordinate 'phi_v'"):
        laminar.xarray.fit(data.drop_vars("phi_v"))
    with pytest.raises(ValueError, match="'angle' is not a dimension"):
        laminar.xarray.fit(data, dim="angle")
    bad = data.copy()
    bad.values[2, 1, 0, 7] = np.inf
    with pytest.raises(ValueError, match="y=2, x=1, channel=0 holds inf at measurement=7"):
        laminar.xarray.fit(bad, quantity="radiance")


def test_the_untied_model_is_batched_lazily_with_its_own_fields():
    """``exp2`` (σ′/T′ free): fit_dask and laminar.xarray.fit give
    fit_batch's rows, σ′/T′'s fields included (and typed: its flags uint8),
    and the fitted maps make an untied textured material."""
    import laminar_brdf.xarray

    g, data = labelled_cube(4, 3, channels=3)
    sets = data.values.reshape(-1, 198)  # (y, x, channel) row-major, as xarray.fit
    lazy = fit_dask(g, da.from_array(sets, chunks=(10, 198)), "exp2", quantity="radiance", uncertainty="jacobian")
    assert tuple(lazy.data_vars) == laminar.distributed.fields("exp2")
    assert "sub_slope" in lazy and lazy["sub_slope_flags"].dtype == np.uint8
    with dask.config.set(scheduler="threads"):
        computed = lazy.compute()
    expected = laminar.fit_batch(g, sets, "exp2", quantity="radiance", uncertainty="jacobian")
    assert_equal_rows(computed, expected)
    records = laminar.distributed.to_records(computed)
    assert records.dtype == laminar.batch_dtype("exp2")
    assert np.isfinite(records["sub_slope"]).all()
    maps = laminar.xarray.fit(data, model="exp2", quantity="radiance", uncertainty="off")
    assert maps["sub_slope"].dims == ("y", "x", "channel")
    np.testing.assert_array_equal(
        maps["sub_slope"].values.reshape(-1),
        laminar.fit_batch(g, sets, "exp2", quantity="radiance", uncertainty="off")["sub_slope"],
    )
    from laminar_brdf.mitsuba_native import textured

    from test_render import mitsuba_variant  # (skips without Mitsuba, unless required)

    mi = mitsuba_variant("llvm_ad_rgb")
    bsdf = mi.load_dict(textured(maps))
    assert "sub_slope.data" in mi.traverse(bsdf).keys()
    # Texel (y, x) = (1, 2) at its uv: each channel the library's exp2 there.
    si = mi.SurfaceInteraction3f()
    si.uv = mi.Point2f((2 + 0.5) / 3, (1 + 0.5) / 4)
    ti, ts, phi = 0.5, 0.7, 2.0
    si.wi = mi.Vector3f(float(np.sin(ts)), 0.0, float(np.cos(ts)))
    wo = mi.Vector3f(*(float(v) for v in (np.sin(ti) * np.cos(phi + np.pi), np.sin(ti) * np.sin(phi + np.pi), np.cos(ti))))
    got = np.array(bsdf.eval(mi.BSDFContext(), si, wo)).ravel()
    for c in range(3):
        texel = maps.isel(y=1, x=2, channel=c)
        params = {p: float(texel[p]) for p in ("slope", "sub_slope", "beta", "n", "a")}
        model = laminar.FittedModel.from_params("exp2", params, amplitude=float(texel["amplitude"] * texel["data_scale"]))
        (pti, pts, pps, _) = laminar.mitsuba._paper_angles(si.wi, wo)
        np.testing.assert_allclose(got[c], model.radiance(pti, pts, pps)[0], rtol=1e-5)
