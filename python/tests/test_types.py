"""The type stubs cover the documented API: ``mypy --strict`` passes on every
``python`` block of the README and of docs/ (test_docs.py runs the same
blocks), and on a module naming every documented name: each
``laminar.<name>`` written anywhere in the README or docs/, each
``Measurements.<name>``/``FittedModel.<name>``/``FitResult.<name>`` and each
``from_<format>`` constructor written in the Python pages. mypy is in
requirements-test.txt; without it the test says SKIPPED, unless
``LAMINAR_REQUIRE_PYTHON=1`` (CI), when it fails."""

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import importable
from test_docs import ROOT, pages, python_blocks

PYTHON_PAGES = [ROOT / "README.md", ROOT / "docs" / "python.md"]
MODULES = ("xarray", "distributed", "mitsuba", "mitsuba_native")
# `laminar.<ext>` in the docs is a file name, not an attribute.
FILE_SUFFIXES = {"h", "py", "pyi", "wasm", "js", "d"}


def documented_names():
    """Dotted names under ``laminar`` that the docs promise."""
    names = set()
    for page in pages():
        for m in re.finditer(r"(?<![\w./-])laminar((?:\.[A-Za-z_]\w*)+)", page.read_text()):
            path = m.group(1)[1:]
            if path.split(".")[-1] not in FILE_SUFFIXES:
                names.add(path)
    for page in PYTHON_PAGES:
        text = page.read_text()
        names.update(m.group(0) for m in re.finditer(r"(?<![\w.])(?:Measurements|FittedModel|FitResult)\.[a-z_]\w*", text))
        names.update(f"Measurements.{m.group(0)}" for m in re.finditer(r"(?<![\w.])from_[a-z]+\b", text))
    return sorted(names)


def api_module():
    """A module that names each documented name (mypy checks each exists)."""
    lines = ["import laminar_brdf as laminar", *(f"import laminar_brdf.{m}" for m in MODULES), ""]
    lines += [f"_{i}: object = laminar.{name}" for i, name in enumerate(documented_names())]
    # Calling the plain-Python entry points checks that they are typed.
    lines += ["", "", "def _calls() -> None:", "    laminar.mitsuba.register()", ""]
    return "\n".join(lines)


def mypy_available():
    return importable(("mypy",), "LAMINAR_REQUIRE_PYTHON")


def test_the_docs_name_the_api():
    names = documented_names()
    for expected in ("MODELS", "GRID_AXES", "mitsuba.register", "Measurements.from_astm", "FittedModel.from_params"):
        assert expected in names, f"{expected} not found among the documented names {names}"


def test_mypy_strict_on_the_documented_api(tmp_path):
    if not mypy_available():
        pytest.skip("mypy is not installed (pip install -r python/requirements-test.txt)")
    files = {"documented_api.py": api_module()}
    for where, code in python_blocks():
        files[re.sub(r"\W", "_", where) + ".py"] = code
    for name, code in files.items():
        (tmp_path / name).write_text(code)
    out = subprocess.run(
        [
            sys.executable, "-m", "mypy", "--strict", "--no-incremental", "--cache-dir", os.devnull,
            # Dask's and xarray's own functions are untyped: calling them is not our stubs' gap.
            "--untyped-calls-exclude", "dask", "--untyped-calls-exclude", "xarray",
            *sorted(files),
        ],
        cwd=tmp_path, capture_output=True, text=True,
    )
    assert out.returncode == 0, f"mypy --strict:\n{out.stdout}{out.stderr}"
