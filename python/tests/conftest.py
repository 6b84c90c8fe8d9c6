"""Shared helpers: the `laminar` CLI the results are compared with, and
small measurement files written by the tests."""

import json
import math
import os
import shutil
import subprocess

import numpy as np
import pytest


def laminar_bin():
    """The CLI binary: $LAMINAR_BIN (set by cli/tests/python.rs and .ci/run)
    or `laminar` on PATH."""
    path = os.environ.get("LAMINAR_BIN") or shutil.which("laminar")
    if not path:
        if os.environ.get("LAMINAR_REQUIRE_PYTHON") == "1":
            pytest.fail("LAMINAR_BIN is not set and `laminar` is not on PATH")
        pytest.skip("the laminar CLI is not available (set LAMINAR_BIN)")
    return path


def importable(modules, required_by):
    """Whether every module of `modules` imports; when one does not and the
    environment variable `required_by` is "1" (CI), the ImportError is raised."""
    import importlib

    try:
        for module in modules:
            importlib.import_module(module)
    except ImportError:
        if os.environ.get(required_by) == "1":
            raise
        return False
    return True


def cli(*args):
    """Runs the CLI; returns stdout (fails the test on a non-zero exit)."""
    done = subprocess.run([laminar_bin(), *map(str, args)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done.stdout


def cli_fits(*args):
    """The `fits` of `laminar fit … --format json`."""
    return json.loads(cli("fit", "--format", "json", *args))["fits"]


#: A small grid that keeps the tests fast (the paper's steps, fewer values).
GRID = {"slope": "0.12:1.72:21", "n": "1.3:1.5:11", "a": "0:1:11", "beta": "0.01:1:100"}
GRID_ARGS = ["--slope", GRID["slope"], "--n", GRID["n"], "--a", GRID["a"], "--beta", GRID["beta"]]


def geometry(k=120):
    """k lab-frame geometries (radians) spread over the hemisphere, away
    from the specular direction."""
    i = np.arange(k) + 0.5
    theta_i = np.radians(5 + 70 * ((i * 0.6180339887) % 1))
    theta_v = np.radians(5 + 70 * ((i * 0.7548776662) % 1))
    phi_v = math.pi * (2 * ((i * 0.5698402910) % 1) - 1) * 0.9
    return np.column_stack([theta_i, np.zeros(k), theta_v, phi_v])


def radiance(g, slope=0.92, beta=0.4, n=1.42, a=0.3, noise=0.01, seed=1):
    """The exp model's normalised radiance at lab geometries `g`, plus seeded noise."""
    paper = np.array([laminar_paper(*row) for row in g])
    import laminar_brdf as laminar

    total = laminar.evaluate("exp", paper[:, 0], paper[:, 1], paper[:, 2], slope, beta, n, a)["total"]
    rng = np.random.default_rng(seed)
    return total / total.max() + noise * rng.standard_normal(len(total))


def laminar_paper(theta_i, phi_i, theta_v, phi_v):
    import laminar_brdf as laminar

    return laminar.paper_angles(theta_i, phi_i, theta_v, phi_v)


def write_csv(path, g, values, channel="value"):
    """A long-format CSV measurement file (lab frame, radians)."""
    return write_channels(path, g, {channel: values})


def write_channels(path, g, channels):
    """A long-format CSV measurement file (lab frame, radians) of several
    channels: ``channels`` maps each name to its values."""
    with open(path, "w") as f:
        f.write(",".join(["theta_i", "phi_i", "theta_v", "phi_v", *channels]) + "\n")
        for row, *v in zip(g, *channels.values()):
            f.write(",".join(repr(float(x)) for x in (*row, *v)) + "\n")
    return path


def paint_material(directory, model, names=("r", "g", "b"), stem="paint"):
    """A jointly fitted material of ``model``: three channels ``names`` of
    the exp model (σ/T 0.6, a 0.05, 0.3 and 0.6) at 150 geometries, written
    as ``stem.csv`` in ``directory`` and fitted by ``laminar fit-joint
    --fits stem.json`` (no intervals, no folds). The CSV's and the fitted-
    model file's paths."""
    g = geometry(150)
    values = [radiance(g, slope=0.6, a=a, seed=s) for a, s in ((0.05, 1), (0.3, 2), (0.6, 3))]
    data = write_channels(directory / f"{stem}.csv", g, dict(zip(names, values)))
    path = directory / f"{stem}.json"
    cli("fit-joint", "--measurements", data, "--quantity", "radiance", "--model", model,
        "--uncertainty", "off", "--folds", 0, "--fits", path)
    return data, path
