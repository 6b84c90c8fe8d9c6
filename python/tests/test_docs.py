"""Every ``python`` block of the READMEs (the repository's, the wheel's)
and of docs/ runs (docs/testing.md), in a directory holding the files the
blocks name: ``felt.csv`` (a long CSV, lab-frame degrees, channels r, g, b
and sigma_r), ``geometry.csv`` (K × 4, radians), ``values.zarr`` (N × K
sets, chunked along N) and ``btf.zarr`` (a (y, x, channel, measurement)
cube with the geometry as coordinates). Blocks that use Dask run only with
the ``dask`` extra (required in CI)."""

import re
import sys
from pathlib import Path

import numpy as np
import pytest

import laminar_brdf as laminar
from conftest import importable

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python" / "examples"))
from btf_cube import cube  # noqa: E402


def pages():
    return [ROOT / "README.md", ROOT / "python" / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


def python_blocks():
    """(page:line, code) of every ```python block."""
    found = []
    for page in pages():
        text = page.read_text()
        for m in re.finditer(r"^```python\n(.*?)^```$", text, flags=re.S | re.M):
            line = text[: m.start()].count("\n") + 1
            found.append((f"{page.relative_to(ROOT)}:{line}", m.group(1)))
    return found


def write_fixtures(directory, with_dask):
    """The files the blocks read (the Zarr stores only `with_dask`)."""
    g_deg = np.array(
        [[ti, 0.0, tv, pv] for ti in (10, 25, 40, 55, 70) for tv in (5, 20, 35, 50, 65) for pv in range(0, 360, 60)],
        dtype=float,
    )
    paper = np.array([laminar.paper_angles(*row) for row in np.radians(g_deg)])
    total = laminar.evaluate("exp", paper[:, 0], paper[:, 1], paper[:, 2], 1.3, 0.4, 1.45, 0.2)["total"]
    brdf = total / np.cos(np.radians(g_deg[:, 0]))
    ripple = 1 + 0.01 * np.sin(np.radians(g_deg[:, 0] + 3 * g_deg[:, 2] + g_deg[:, 3]) * 7)
    rows = np.column_stack([g_deg, brdf * ripple, 0.8 * brdf / ripple, 0.6 * brdf * ripple, 0.01 * brdf])
    np.savetxt(
        directory / "felt.csv", rows, delimiter=",", comments="",
        header="theta_i,phi_i,theta_v,phi_v,r,g,b,sigma_r",
    )
    if not with_dask:
        return
    import dask.array as da
    import xarray as xr

    g, values = cube(4, 4, k=198, channels=3)
    np.savetxt(directory / "geometry.csv", g, delimiter=",", comments="", header="theta_i,phi_i,theta_v,phi_v")
    da.from_array(values.reshape(-1, 198), chunks=(16, 198)).to_zarr(str(directory / "values.zarr"))
    data = values.reshape(3, 4, 4, 198).transpose(1, 2, 0, 3)
    coords = {
        "y": np.arange(4),
        "x": np.arange(4),
        "channel": [0, 1, 2],
        **{name: ("measurement", g[:, i]) for i, name in enumerate(("theta_i", "phi_i", "theta_v", "phi_v"))},
    }
    cube_da = xr.DataArray(data, dims=("y", "x", "channel", "measurement"), coords=coords)
    xr.Dataset({"radiance": cube_da}).chunk({"y": 2}).to_zarr(str(directory / "btf.zarr"))


def dask_available():
    return importable(("dask.array", "xarray", "zarr"), "LAMINAR_REQUIRE_DASK")


def test_the_docs_have_python_blocks():
    assert len(python_blocks()) >= 3


@pytest.mark.parametrize("where,code", python_blocks(), ids=[w for w, _ in python_blocks()])
def test_python_block_runs(where, code, tmp_path, monkeypatch):
    with_dask = "dask" in code or "xarray" in code
    if with_dask and not dask_available():
        pytest.skip(f"{where} needs the dask extra (pip install './python[dask]')")
    write_fixtures(tmp_path, with_dask)
    monkeypatch.chdir(tmp_path)
    try:
        exec(compile(code, where, "exec"), {"__name__": "__docs__"})
    except Exception as e:  # name the block, not this file
        pytest.fail(f"{where}: {type(e).__name__}: {e}")
