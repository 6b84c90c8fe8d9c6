"""The Python package against the CLI on the same input, and its errors."""

import json
import math
import os
from pathlib import Path

import numpy as np
import pytest

import laminar_brdf as laminar
from conftest import GRID, GRID_ARGS, cli, cli_fits, geometry, radiance, write_channels, write_csv


def test_evaluate_broadcasts_and_equals_the_cli(tmp_path):
    theta_s = np.linspace(0.0, 1.4, 7)
    out = laminar.evaluate("gauss", 0.4, theta_s[:, None], [0.0, 2.5], 0.8, 0.3, 1.45, 0.2)
    assert set(out) == {"fresnel_in", "fresnel_out", "absorb_in", "absorb_out", "surface", "subsurface", "total"}
    assert out["total"].shape == (7, 2)
    geo = tmp_path / "g.csv"
    geo.write_text("theta_i,theta_s,phi_s\n" + "".join(f"0.4,{float(t)!r},2.5\n" for t in theta_s))
    text = cli("eval", "--model", "gauss", "--slope", 0.8, "--beta", 0.3, "--n", 1.45, "--a", 0.2, "--geometry", geo)
    rows = [line.split(",") for line in text.strip().splitlines()[1:]]
    header = text.splitlines()[0].split(",")
    for name in out:
        col = header.index(name)
        expected = np.array([float(r[col]) for r in rows])
        # Bit for bit: the CLI prints the shortest representation that reads back exactly.
        assert np.array_equal(out[name][:, 1], expected), name
    f32 = laminar.evaluate("gauss", 0.4, theta_s, 2.5, 0.8, 0.3, 1.45, 0.2, precision="f32")["total"]
    assert np.allclose(f32, out["total"][:, 1], rtol=1e-5) and not np.array_equal(f32, out["total"][:, 1])


def test_an_untied_model_takes_its_subsurface_slope(tmp_path):
    theta_s = np.linspace(0.0, 1.4, 5)
    out = laminar.evaluate("exp2", 0.4, theta_s, 0.3, 0.2, 0.3, 1.45, 0.2, sub_slope=1.5)
    geo = tmp_path / "g.csv"
    geo.write_text("theta_i,theta_s,phi_s\n" + "".join(f"0.4,{float(t)!r},0.3\n" for t in theta_s))
    args = ("--slope", 0.2, "--sub-slope", 1.5, "--beta", 0.3, "--n", 1.45, "--a", 0.2, "--geometry", geo)
    text = cli("eval", "--model", "exp2", *args)
    header = text.splitlines()[0].split(",")
    rows = [line.split(",") for line in text.strip().splitlines()[1:]]
    for name in out:
        expected = np.array([float(r[header.index(name)]) for r in rows])
        assert np.array_equal(out[name], expected), name
    # The surface is the tied model's at σ/T, the subsurface the tied
    # model's at σ′/T′.
    surface = laminar.evaluate("exp", 0.4, theta_s, 0.3, 0.2, 0.3, 1.45, 0.2)
    subsurface = laminar.evaluate("exp", 0.4, theta_s, 0.3, 1.5, 0.3, 1.45, 0.2)
    assert np.array_equal(out["surface"], surface["surface"])
    assert np.array_equal(out["subsurface"], subsurface["subsurface"])
    with pytest.raises(ValueError, match="sub_slope: exp2 frees"):
        laminar.evaluate("exp2", 0.4, theta_s, 0.3, 0.2, 0.3, 1.45, 0.2)
    with pytest.raises(ValueError, match="sub_slope: exp ties"):
        laminar.evaluate("exp", 0.4, theta_s, 0.3, 0.2, 0.3, 1.45, 0.2, sub_slope=1.5)


def test_fit_of_a_csv_equals_the_cli(tmp_path):
    g = geometry()
    path = write_csv(tmp_path / "set.csv", g, radiance(g))
    m = laminar.Measurements.from_csv(path, quantity="radiance")
    assert m.channel == "value" and len(m) == len(g)
    result = laminar.fit(m, "exp", grid=GRID)
    fits = cli_fits("--measurements", path, "--quantity", "radiance", "--models", "exp", *GRID_ARGS)
    assert json.loads(result.to_json())["fits"] == fits
    # The file's fitted model is the refined one; the grid's is kept beside it.
    assert result.params == fits[0]["fitted"]["params"]
    assert result.grid_params == fits[0]["grid_fitted"]["params"]
    assert result.parameters == fits[0]["parameters"] and set(result.parameters) == {"slope", "beta", "n", "a"}
    assert result.correlations == fits[0]["correlations"]
    # The data were made at a grid point with 1% noise: σ/T comes back
    # exactly on the grid, and Δ_RMS is at the noise level,
    # 100 · 0.01 · sqrt(K) / K; refinement only lowers it.
    assert result.grid_params["slope"] == pytest.approx(0.92, abs=1e-9)
    assert result.rms == result.rms_refined <= result.rms_grid < 1.2 * 100 * 0.01 / np.sqrt(len(g))
    # Every parameter has a refined value inside its own 68% interval, or,
    # when the data do not determine it within this small box, says so
    # (its 95% interval is the whole box; the fitted model keeps a value).
    for name, p in result.parameters.items():
        if "not_identified" in p["flags"]:
            assert p["refined"] == "not_identified" and [p["lo95"], p["hi95"]] == p["box"], name
            assert isinstance(result.params[name], float), name
            continue
        assert p["lo68"] <= p["refined"] <= p["hi68"], name
        assert p["lo95"] <= p["lo68"] and p["hi68"] <= p["hi95"], name
        assert p["interval"] == "robust", name  # the profile calibrated by the sandwich


def test_relative_noise_and_untied_models_equal_the_cli(tmp_path):
    g = geometry()
    path = write_csv(tmp_path / "set.csv", g, radiance(g))
    m = laminar.Measurements.from_csv(path, quantity="radiance")
    result = laminar.fit(m, "exp2", grid=GRID, noise="relative", noise_floor=0.05)
    fits = cli_fits(
        "--measurements", path, "--quantity", "radiance", "--models", "exp2", *GRID_ARGS,
        "--noise", "relative", "--noise-floor", "0.05",
    )
    assert json.loads(result.to_json())["fits"] == fits
    assert set(result.params) == {"slope", "sub_slope", "beta", "n", "a"}
    assert fits[0]["adequacy"]["chi2_p"] is None  # the scale is estimated
    given = laminar.fit(m, "exp2", grid=GRID)
    assert given.params != result.params
    with pytest.raises(ValueError, match="noise: unknown noise `poisson`"):
        laminar.fit(m, "exp", grid=GRID, noise="poisson")
    with pytest.raises(ValueError, match="noise_floor: noise floor `0` is not in"):
        laminar.fit(m, "exp", grid=GRID, noise="relative", noise_floor=0.0)
    with pytest.raises(ValueError, match="model exp2 frees the subsurface slope"):
        laminar.compare(m, ["exp", "exp2"], objective="paper")


def test_near_mirror_values_are_left_out_as_the_cli_does(tmp_path):
    """``with_specular_tolerance``: three geometries near the mirror are
    fitted by default and left out within 0.05 rad, as the CLI's
    ``--specular-tolerance``; a negative tolerance is refused."""
    g = geometry()
    near = np.array([[0.5, 0.0, 0.51, math.pi - 0.01], [0.8, 0.0, 0.78, math.pi - 0.02], [0.3, 0.0, 0.3, -math.pi + 0.03]])
    g = np.vstack([g, near])
    path = tmp_path / "near.csv"
    with open(path, "w") as f:
        f.write("theta_i,phi_i,theta_v,phi_v,value\n")
        for row, v in zip(g, radiance(g)):
            f.write(",".join(repr(float(x)) for x in (*row, v)) + "\n")
    m = laminar.Measurements.from_csv(path, quantity="radiance")
    assert laminar.fit(m, "exp", grid=GRID, uncertainty="off").measurements == 123
    narrow = m.with_specular_tolerance(0.05)
    assert len(narrow) == len(m) == 123 and narrow.channel == m.channel
    fitted = laminar.fit(narrow, "exp", grid=GRID, uncertainty="off")
    [entry] = cli_fits("--measurements", path, "--quantity", "radiance", "--models", "exp", *GRID_ARGS,
                       "--uncertainty", "off", "--specular-tolerance", 0.05)
    assert fitted.measurements == entry["measurements"] == 120
    assert fitted.params == pytest.approx(entry["params"], rel=0, abs=1e-9)
    with pytest.raises(ValueError, match="tolerance"):
        m.with_specular_tolerance(-1.0)


def test_fit_joint_equals_the_cli(tmp_path):
    """One fit across two channels: the CLI's `fit-joint` numbers, the
    shared parameters once, each channel's a with its intervals."""
    import csv

    g = geometry()
    r, b = radiance(g, a=0.1, seed=3), radiance(g, a=0.6, seed=4)
    path = write_channels(tmp_path / "paint.csv", g, {"r": r, "b": b})
    channels = [laminar.Measurements.from_csv(path, quantity="radiance", channel=c) for c in ("r", "b")]
    joint = laminar.fit_joint(channels, "exp", grid=GRID, noise="relative", resamples=30, seed=2)
    text = cli("fit-joint", "--measurements", path, "--quantity", "radiance", "--model", "exp", *GRID_ARGS,
               "--noise", "relative", "--resamples", 30, "--seed", 2)
    rows = list(csv.DictReader(text.splitlines()))
    assert [c["channel"] for c in joint["channels"]] == [row["channel"] for row in rows] == ["r", "b"]
    assert joint["model"] == "exp" and set(joint["shared"]) == {"slope", "n"}
    for name, v in joint["shared"].items():
        for key in ("", "_lo68", "_hi68", "_lo95", "_hi95"):
            got = v["value"] if key == "" else v[key[1:]]
            assert got == float(rows[0][name + key]) == float(rows[1][name + key]), name + key
    for c, row in zip(joint["channels"], rows):
        assert c["a"]["value"] == float(row["a"]) and c["a"]["lo95"] == float(row["a_lo95"])
        assert c["beta"] == float(row["beta"]) and c["sse"] == float(row["sse"])
        assert c["adequacy"]["runs_p"] == float(row["runs_p"])
        assert c["adequacy"]["lack_of_fit"] == (row["lack_of_fit"] == "true")
        cv = c["cross_validation"]
        assert cv["folds"] == 5 and cv["rms"] == float(row["cv_rms"]) and cv["in_sample"] == float(row["in_sample_rms"])
    assert joint["parameters"] == 8 and joint["resamples"] == 30
    assert joint["channels"][0]["a"]["value"] < joint["channels"][1]["a"]["value"]
    # The two channels' absorptions differ (0.1 and 0.6 made them): the
    # test of one a for both says so, as the CLI does.
    chromatic = joint["chromatic"]
    assert chromatic["p_value"] == float(rows[0]["chromatic_p"]) < 1e-3 and tuple(chromatic["df"]) == (1, 29)
    # A tied model's σ/T is its subsurface's too: the roughness test is not made, as in the CLI.
    assert joint["shared_roughness"]["untested"] == rows[0]["roughness_note"] != ""
    # The variants ranked as in the CLI: joint and separate (a tied model
    # has no roughness-per-channel fit).
    variants = {v["variant"]: v for v in joint["variants"]}
    assert set(variants) == {"joint", "separate"} and variants["joint"]["parameters"] == 8
    for name, v in variants.items():
        assert v["delta"] == float(rows[0]["delta_aicc_" + name])
    assert rows[0]["delta_aicc_roughness_per_channel"] == ""
    assert [v["variant"] for v in joint["variants"] if v["rank"] == 1] == [rows[0]["best_variant"]]
    untied = laminar.fit_joint(channels, grid=GRID, uncertainty="off")
    assert untied["model"] == "exp2" and set(untied["shared"]) == {"slope", "sub_slope", "n"}
    assert untied["resamples"] == 0 and untied["shared"]["n"]["lo95"] is None
    unvalidated = laminar.fit_joint(channels, grid=GRID, uncertainty="off", folds=0)
    assert all(c["cross_validation"] is None for c in unvalidated["channels"])
    with pytest.raises(ValueError, match="1 channel given"):
        laminar.fit_joint(channels[:1])
    with pytest.raises(TypeError, match="a sequence of Measurements"):
        laminar.fit_joint([1, 2])


def test_compare_equals_the_cli_with_every_model(tmp_path):
    g = geometry()
    path = write_csv(tmp_path / "set.csv", g, radiance(g))
    m = laminar.Measurements.from_csv(path, quantity="radiance")
    results = laminar.compare(m, grid=GRID, folds=4, seed=7)
    models = ",".join(laminar.MODELS)
    fits = cli_fits("--measurements", path, "--quantity", "radiance", "--models", models, "--folds", 4, "--seed", 7, *GRID_ARGS)
    assert [json.loads(r.to_json())["fits"][0] for r in results] == fits
    assert [r.model for r in results] == list(laminar.MODELS)
    assert sorted(r.rank["rank"] for r in results)[0] == 1
    assert sum(r.rank["weight"] for r in results) == pytest.approx(1.0)
    for r, f in zip(results, fits):
        assert r.cross_validation == f["cross_validation"] and r.cross_validation["folds"] == 4
        assert r.cross_validation["rms"] >= r.cross_validation["in_sample"]
        assert r.information == f["information"] and r.adequacy == f["adequacy"]
        assert set(r.graphics) == {"cosine_rms", "cube_root"}
    # One model alone is neither ranked nor cross-validated.
    alone = laminar.fit(m, "exp", grid=GRID)
    assert alone.rank is None and alone.cross_validation is None and alone.adequacy["lack_of_fit"] in (True, False)
    with pytest.raises(ValueError, match="folds"):
        laminar.compare(m, ["exp", "gauss"], folds=1)
    with pytest.raises(ValueError, match="models"):
        laminar.compare(m, ["exp", "lambert"])


def test_from_arrays_equals_from_csv_and_predict_reproduces_rms(tmp_path):
    g = geometry()
    values = radiance(g, seed=4)
    a = laminar.Measurements.from_arrays(*g.T, values, quantity="radiance")
    b = laminar.Measurements.from_csv(write_csv(tmp_path / "s.csv", g, values), quantity="radiance")
    fa, fb = laminar.fit(a, "gauss", grid=GRID, threads=1), laminar.fit(b, "gauss", grid=GRID)
    assert (fa.params, fa.rms, fa.chi2_dof) == (fb.params, fb.rms, fb.chi2_dof)
    predicted = fa.predict(*g.T)
    data = values / values.max()
    rms = 100 * np.sqrt(np.sum((data - predicted) ** 2)) / len(data)
    assert abs(rms - fa.rms) <= 1e-12 * fa.rms
    assert np.allclose(fa.predict(*g.T, radiance=True), predicted * values.max())


@pytest.mark.parametrize("model", ["exp", "exp2"])
def test_fit_batch_equals_fit_of_each_row(model):
    g = geometry(90)
    values = np.stack([radiance(g, slope=s, a=a, seed=i) for i, (s, a) in enumerate([(0.6, 0.1), (1.2, 0.5), (1.6, 0.8)])])
    out = laminar.fit_batch(g, values, model, grid=GRID, quantity="radiance")
    assert out.dtype == laminar.batch_dtype(model) and out.shape == (3,)
    # The tied models' fields, and the untied ones' with σ′/T′'s besides.
    extra = [n for n in out.dtype.names if n not in laminar.BATCH_COLUMNS]
    assert extra == ([] if model == "exp" else ["sub_slope", *(f"sub_slope_{f}" for f in ("lo68", "hi68", "lo95", "hi95", "sd", "flags"))])
    assert [n for n in out.dtype.names if n in laminar.BATCH_COLUMNS] == list(laminar.BATCH_COLUMNS)
    assert [n for n, _ in laminar.batch_fields(model)] == list(out.dtype.names)
    for row, result in zip(values, out):
        alone = laminar.fit(laminar.Measurements.from_arrays(*g.T, row, quantity="radiance"), model, grid=GRID)
        for name, value in alone.params.items():
            # A value the data do not determine is NaN in the batch (its
            # flags say so), as `fit`'s CSV says not_identified.
            unknown = "not_identified" in alone.parameters[name]["flags"]
            assert np.array_equal(result[name], np.nan if unknown else value, equal_nan=True), name
        assert result["rms"] == alone.rms and result["search_rms"] == alone.search_rms
        # The Ragheb–Hancock side result is the tied models' (NaN for exp2's).
        assert np.array_equal(result["rh_rms"], np.nan if alone.rh is None else alone.rh["rms"], equal_nan=True)
        for name, q in alone.parameters.items():
            want = [q["lo68"], q["hi68"], q["lo95"], q["hi95"]]
            got = [result[f"{name}_{end}"] for end in ("lo68", "hi68", "lo95", "hi95")]
            assert got == want, name
            assert result[f"{name}_flags"] == sum(laminar.FLAG_BITS[f] for f in q["flags"]), name
            assert np.array_equal(result[f"{name}_sd"], np.nan if q["sd"] is None else q["sd"], equal_nan=True)
    one_thread = laminar.fit_batch(g, values, model, grid=GRID, threads=1, quantity="radiance")
    for field in out.dtype.names:
        assert np.array_equal(one_thread[field], out[field], equal_nan=True), field


@pytest.mark.skipif(not os.environ.get("CURET_DIR"), reason="CURET_DIR is not set")
def test_curet_fit_equals_the_cli():
    data = os.environ["CURET_DIR"]
    result = laminar.fit(laminar.Measurements.from_curet(data, 21), "exp")
    fits = cli_fits("--data", data, "--samples", 21, "--models", "exp")
    assert json.loads(result.to_json())["fits"] == fits


def test_merl_file_round_trip_equals_the_cli(tmp_path):
    g = geometry()
    csv = write_csv(tmp_path / "s.csv", g, radiance(g) / np.cos(g[:, 0]))
    fit_json = tmp_path / "fit.json"
    cli("fit", "--measurements", csv, "--models", "exp", "--format", "json", "--out", fit_json, *GRID_ARGS)
    merl = tmp_path / "m.binary"
    cli("export", "--fit", fit_json, "--merl", merl)
    geo = tmp_path / "g.csv"
    geo.write_text("theta_i,phi_i,theta_v,phi_v\n" + "".join(",".join(map(repr, map(float, r))) + "\n" for r in g))
    m = laminar.Measurements.from_merl(merl, geo, channel="r")
    result = laminar.fit(m, "exp", grid=GRID)
    fits = cli_fits("--measurements", merl, "--sample-at", geo, "--channels", "r", "--models", "exp", *GRID_ARGS)
    assert json.loads(result.to_json())["fits"] == fits


def test_errors_name_the_parameter_file_and_line(tmp_path):
    with pytest.raises(ValueError, match="beta"):
        laminar.evaluate("exp", 0.1, 0.1, 0.0, 1.0, 1.5, 1.4, 0.1)
    with pytest.raises(ValueError, match="rh-exp is the a = 0 model"):
        laminar.evaluate("rh-exp", 0.1, 0.1, 0.0, 1.0, 0.5, 1.4, 0.1)
    with pytest.raises(ValueError, match="model"):
        laminar.evaluate("lambert", 0.1, 0.1, 0.0, 1.0, 0.5, 1.4, 0.1)
    bad = tmp_path / "bad.csv"
    bad.write_text("theta_i,phi_i,theta_v,phi_v,value\n0.1,0,0.2,1,0.5\n0.1,0,x,1,0.5\n")
    with pytest.raises(ValueError, match=r"bad\.csv.*3"):
        laminar.Measurements.from_csv(bad)
    with pytest.raises(OSError, match="missing.csv"):
        laminar.Measurements.from_csv(tmp_path / "missing.csv")
    g = geometry(20)
    m = laminar.Measurements.from_arrays(*g.T, radiance(g), quantity="radiance")
    with pytest.raises(ValueError, match="axis a"):
        laminar.fit(m, grid={"a": "0:2:3"})
    with pytest.raises(ValueError, match="uncertainty"):
        laminar.fit(m, uncertainty="jackknife")
    with pytest.raises(ValueError, match="values per set"):
        laminar.fit_batch(g, np.ones((2, 7)))
    with pytest.raises(ValueError, match="row 1"):
        laminar.fit_batch(g, np.stack([np.ones(20), -np.ones(20)]), grid=GRID)


def test_conversions_name_the_parameter():
    """Arguments of the wrong kind are a ValueError naming the parameter
    (they were numpy's or PyO3's errors naming none), real integers are
    numbers, and complex arrays are refused where numpy would drop their
    imaginary part with a warning only (issue 55, items 6 and 7)."""
    g = geometry(20)
    values = radiance(g)
    m = laminar.Measurements.from_arrays(*g.T, values, quantity="radiance")
    for kwargs, name in [
        ({"seed": -1}, "seed"),
        ({"seed": 1.5}, "seed"),
        ({"resamples": 2**70}, "resamples"),
        ({"refine": "yes"}, "refine"),
        ({"refine": 1}, "refine"),
        ({"threads": -2}, "threads"),
    ]:
        with pytest.raises(ValueError, match=f"^{name}: "):
            laminar.fit(m, "exp", grid=GRID, **kwargs)
    with pytest.raises(ValueError, match="^folds: "):
        laminar.compare(m, ["exp", "gauss"], grid=GRID, folds=-1)
    with pytest.raises(ValueError, match="^refine: "):
        laminar.fit_batch(g, values[None, :], grid=GRID, refine="no")
    # Integer arrays are numbers; a complex or text array names itself.
    ints = laminar.Measurements.from_arrays(
        np.zeros(3, dtype=np.int64), np.zeros(3, dtype=np.int64), np.array([0.1, 0.2, 0.3]), np.zeros(3), np.ones(3)
    )
    assert len(ints) == 3
    with pytest.raises(ValueError, match="^phi_v: complex values"):
        laminar.Measurements.from_arrays(*g[:, :3].T, g[:, 3] + 1j, values)
    with pytest.raises(ValueError, match="^sigma: values of type"):
        laminar.Measurements.from_arrays(*g.T, values, sigma=np.array(["a"] * 20))
    with pytest.raises(ValueError, match="^values: complex values"):
        laminar.fit_batch(g, values[None, :] + 0j, grid=GRID)
    with pytest.raises(ValueError, match="^geometry: complex values"):
        laminar.fit_batch(g + 0j, values[None, :], grid=GRID)
    with pytest.raises(ValueError, match=r"^values: shape \(20,\)"):
        laminar.fit_batch(g, values, grid=GRID)
    with pytest.raises(ValueError, match="^beta: complex values"):
        laminar.evaluate("exp", 0.1, 0.1, 0.0, 1.0, 0.5 + 0j, 1.4, 0.1)
    # Numpy's own integers and bools are taken where Python's are.
    fit = laminar.fit(m, "exp", grid=GRID, seed=np.uint8(3), refine=np.bool_(False))
    assert fit.params


def test_the_gil_is_released_while_fitting():
    """A Python thread keeps running while a batch fit works."""
    import threading
    import time

    g = geometry()
    values = np.stack([radiance(g, seed=i) for i in range(400)])
    ticks = []
    done = threading.Event()

    def tick():
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    t = threading.Thread(target=tick)
    t.start()
    start = time.perf_counter()
    laminar.fit_batch(g, values, "exp", threads=1, quantity="radiance")
    elapsed = time.perf_counter() - start
    done.set()
    t.join()
    # The ticking thread kept running during the (paper-grid) fits: about one
    # tick per 1–2 ms; with the GIL held it would tick once or twice.
    assert len(ticks) >= min(20, elapsed / 0.005), (len(ticks), elapsed)


def test_package_ships_type_stubs():
    root = Path(laminar.__file__).parent
    assert (root / "py.typed").exists() and (root / "__init__.pyi").exists() and (root / "_laminar.pyi").exists()


_MEMORY_SCRIPT = """
import re, resource, sys
import numpy as np
import laminar_brdf as laminar

def limit(extra):
    # The address space used now, plus `extra` bytes.
    size = int(re.search(r"VmSize:\\s+(\\d+) kB", open("/proc/self/status").read()).group(1)) * 1024
    resource.setrlimit(resource.RLIMIT_AS, (size + extra, size + extra))

g = np.array([[0.1, 0.0, 0.2, 3.0], [0.3, 0.0, 0.4, 3.0], [0.5, 0.0, 0.2, 1.0], [0.2, 0.0, 0.6, 2.0]])
laminar.fit_batch(g, np.full((2, 4), 0.5), "exp", refine=False, uncertainty="off")  # threads up first
try:
    if sys.argv[1] == "evaluate":
        theta_i = np.full(20_000_000, 0.3)
        limit(1_500 << 20)  # the inputs fit (7 × 160 MB), the outputs do not
        laminar.evaluate("exp", theta_i, 0.2, 0.5, 1.2, 0.4, 1.4, 0.3)
    else:
        values = np.full((10_000_000, 4), 0.5)
        limit(1 << 30)  # the input fits (320 MB), the results (1.6 GB) do not
        laminar.fit_batch(g, values, "exp")
    print("no error")
except MemoryError as e:
    print("MemoryError:", e)
"""


@pytest.mark.skipif(not Path("/proc/self/status").exists(), reason="needs Linux's /proc to limit memory")
@pytest.mark.parametrize("call", ["evaluate", "fit_batch"])
def test_too_little_memory_raises_memory_error(call):
    """A size the caller's arrays imply is reserved fallibly: MemoryError,
    not an interpreter killed by SIGABRT."""
    import subprocess
    import sys

    run = subprocess.run([sys.executable, "-c", _MEMORY_SCRIPT, call], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert run.stdout.startswith("MemoryError: not enough memory for"), run.stdout + run.stderr


_ARGUMENTS_SCRIPT = """
import random, sys
import numpy as np
import laminar_brdf as laminar

rng = random.Random(24)
g = np.array([[0.1, 0.0, 0.2, 3.0], [0.3, 0.0, 0.4, 3.0], [0.5, 0.0, 0.2, 1.0], [0.2, 0.0, 0.6, 2.0]])
m = laminar.Measurements.from_arrays(*g.T, np.array([0.5, 0.4, 0.3, 0.2]), quantity="radiance")
pool = [
    None, True, 0, -1, 0.3, 1.48, 1e308, float("nan"), float("inf"), 2**70, "", "exp", "rh-gauss",
    "1.2", "radiance", "x" * 10_000, "\\x00\\x1b[2J", [], [0.3, 0.2], ["0.3"], {}, {"slope": 3}, {"slope": "1:2:x"},
    np.zeros(0), np.zeros(3), np.full((2, 4), 0.5), np.full((2, 3), np.nan), np.zeros((2, 2, 2)),
    np.array(["a"]), np.arange(4, dtype=np.int8), g, m, object(), b"bytes", 1j,
]
functions = [
    (laminar.evaluate, 8), (laminar.fit, 2), (laminar.compare, 2), (laminar.fit_batch, 3), (laminar.paper_angles, 4),
    (laminar.Measurements.from_arrays, 5), (laminar.Measurements.from_csv, 1),
    (laminar.Measurements.from_merl, 2), (laminar.Measurements.from_curet, 2),
]
tally = {"calls": 0, "returned": 0, "raised": 0}
for _ in range(int(sys.argv[1])):
    f, arity = rng.choice(functions)
    args = [rng.choice(pool) for _ in range(arity)]
    tally["calls"] += 1
    try:
        f(*args)
        tally["returned"] += 1
    except (TypeError, ValueError, OverflowError, OSError, MemoryError, KeyError, IndexError):
        tally["raised"] += 1
# Still working after every call.
assert laminar.evaluate("exp", 0.3, 0.2, 0.5, 1.2, 0.4, 1.4, 0.3)["total"].shape == ()
print(tally)
"""


def test_every_function_takes_arguments_of_any_type():
    """Seeded draws of arguments of every type into every function: each
    returns or raises a Python exception (a panic or an abort would end the
    subprocess), and the module keeps working."""
    import subprocess
    import sys

    run = subprocess.run([sys.executable, "-c", _ARGUMENTS_SCRIPT, "3000"], capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr[-3000:]
    tally = eval(run.stdout)
    assert tally["calls"] == 3000 and tally["returned"] > 0 and tally["raised"] > 0, tally


def stub_literals():
    """The ``Literal`` aliases of ``laminar/_laminar.pyi``: {name: values}."""
    import ast

    tree = ast.parse((Path(laminar.__file__).parent / "_laminar.pyi").read_text())
    found = {}
    for node in tree.body:
        value = getattr(node, "value", None)
        if isinstance(node, ast.Assign) and isinstance(value, ast.Subscript) and getattr(value.value, "id", "") == "Literal":
            elts = value.slice.elts if isinstance(value.slice, ast.Tuple) else [value.slice]
            found[node.targets[0].id] = [e.value for e in elts]
    return found


def test_the_stubs_literals_are_the_values_the_library_takes(tmp_path):
    """Every value of each option's ``Literal`` in the stubs is accepted,
    and a value outside it is refused with a ValueError naming the option."""
    lit = stub_literals()
    assert set(lit) == {"Model", "LayeredModel", "Objective", "Uncertainty", "Quantity", "AngleUnit", "Precision", "Noise"}
    # The model aliases are the library's descriptor, in its order.
    assert tuple(lit["Model"]) == tuple(laminar.MODELS)
    assert tuple(lit["LayeredModel"]) == tuple(m for m, info in laminar.MODELS.items() if info["correlation"])
    for model in lit["LayeredModel"]:
        sub_slope = 0.7 if laminar.MODELS[model]["params"][1] == "sub_slope" else None
        for precision in lit["Precision"]:
            laminar.evaluate(model, 0.3, 0.2, 0.5, 1.2, 0.4, 1.4, 0.0, sub_slope=sub_slope, precision=precision)
    for bad in [("jensen", "f64"), ("exp", "f16")]:
        with pytest.raises(ValueError):
            laminar.evaluate(bad[0], 0.3, 0.2, 0.5, 1.2, 0.4, 1.4, 0.0, precision=bad[1])
    g = np.array([[ti, 0.0, tv, pv] for ti in (0.2, 0.5, 0.8) for tv in (0.1, 0.4, 0.7, 1.0) for pv in (0.5, 1.5, 2.5)])
    paper = np.array([laminar.paper_angles(*row) for row in g])
    values = laminar.evaluate("exp", paper[:, 0], paper[:, 1], paper[:, 2], 1.3, 0.4, 1.45, 0.2)["total"]
    for quantity in lit["Quantity"]:
        m = laminar.Measurements.from_arrays(*g.T, values, quantity=quantity)
    for model in lit["Model"]:
        for objective in lit["Objective"]:
            if objective == "paper" and "sub_slope" in laminar.MODELS[model]["params"]:
                with pytest.raises(ValueError, match=f"model {model} frees the subsurface slope"):
                    laminar.fit(m, model, refine=False, uncertainty="off", objective=objective)
                continue
            r = laminar.fit(m, model, refine=False, uncertainty="off", objective=objective)
            # Every parameter of the descriptor is in the result, by its name.
            assert list(r.params) == laminar.MODELS[model]["params"], model
    # Every grid axis is taken by name; another name is refused, naming them.
    for axis in laminar.GRID_AXES:
        laminar.fit(m, "exp", refine=False, uncertainty="off", grid={axis: "0.3:0.6:2" if axis != "n" else "1.3:1.5:2"})
    with pytest.raises(ValueError, match="slope, beta, n, a"):
        laminar.fit(m, "exp", grid={"sigma": "0:1:2"})
    for uncertainty in lit["Uncertainty"]:
        laminar.fit(m, "exp", uncertainty=uncertainty)
    # The grid stage's arithmetic: f32 finds the same minimum of these
    # noiseless data as f64, in fit, compare and fit_batch alike.
    by_precision = {p: laminar.fit(m, "exp", precision=p) for p in lit["Precision"]}
    compared = {p: laminar.compare(m, ["exp"], folds=0, precision=p)[0] for p in lit["Precision"]}
    batch = {p: laminar.fit_batch(g, values[None, :], "exp", precision=p) for p in lit["Precision"]}
    for name, value in by_precision["f64"].params.items():
        assert by_precision["f32"].params[name] == pytest.approx(value, rel=1e-6, abs=1e-9), name
        assert compared["f32"].params[name] == pytest.approx(value, rel=1e-6, abs=1e-9), name
        assert batch["f32"][name][0] == pytest.approx(batch["f64"][name][0], rel=1e-6, abs=1e-9), name
    csv = tmp_path / "m.csv"
    csv.write_text("theta_i,phi_i,theta_v,phi_v,value\n" + "".join(f"{r[0]},{r[1]},{r[2]},{r[3]},{v}\n" for r, v in zip(g, values)))
    for unit in lit["AngleUnit"]:
        laminar.Measurements.from_csv(csv, angles=unit)
    for noise in lit["Noise"]:
        laminar.fit(m, "exp", refine=False, uncertainty="off", noise=noise)
    for call in [
        lambda: laminar.fit(m, "exp", noise="poisson"),
        lambda: laminar.fit(m, "lambert"),
        lambda: laminar.fit(m, "exp", objective="max"),
        lambda: laminar.fit(m, "exp", uncertainty="some"),
        lambda: laminar.fit(m, "exp", precision="f16"),
        lambda: laminar.compare(m, ["exp"], precision="half"),
        lambda: laminar.fit_batch(g, values[None, :], "exp", precision="f16"),
        lambda: laminar.Measurements.from_arrays(*g.T, values, quantity="watts"),
        lambda: laminar.Measurements.from_csv(csv, angles="grad"),
    ]:
        with pytest.raises(ValueError):
            call()


def test_the_real_spectral_sources_read_as_the_cli_does(tmp_path):
    """The three real sources' readers (ASTM E1392, NIST's CSV, RGL's
    .bsdf): each channel a Measurements whose fit is the CLI's on the same
    file, and a defect a ValueError naming the file and line."""
    astm = tmp_path / "paint.astm"
    astm.write_text(
        "NUM_POINTS 3\nVARS theta_i,phi_i,theta_s,phi_s,450nm,550nm\n\n"
        "0.5,0,0.4,3.0,0.09,0.03\n0.5,0,0.6,2.0,0.08,0.02\n0.3,0,0.3,3.0,1.2,0.9\n"
    )
    m = laminar.Measurements.from_astm(astm, channel="550nm")
    assert m.channels == ["450nm", "550nm"] and m.channel == "550nm" and len(m) == 3
    nist = tmp_path / "ptfe.csv"
    nist.write_text(
        "lambda,thetai,phi,thetar,phir,f_r11\n0.532,-30,0,20,10,0.31\n0.532,-30,0,40,170,0.29\n"
        "1.064,-30,0,20,10,0.32\n1.064,-30,0,40,170,0.30\n"
    )
    assert laminar.Measurements.from_nist(nist, channel="1064nm").channels == ["532nm", "1064nm"]
    with pytest.raises(ValueError, match="channel: the set has channels 450nm, 550nm"):
        laminar.Measurements.from_astm(astm)
    astm.write_text("VARS theta_i,phi_i,theta_s,phi_s,R\n\n0.5,0,x,3.0,0.09\n")
    with pytest.raises(ValueError, match=r"paint\.astm:3: column 3 \(theta_s\)"):
        laminar.Measurements.from_astm(astm)
    bad = tmp_path / "m.bsdf"
    bad.write_bytes(b"not a tensor")
    with pytest.raises(ValueError, match=r"m\.bsdf: byte 0: not a tensor file"):
        laminar.Measurements.from_rgl(bad)
    rgl = os.environ.get("RGL_DIR")
    if rgl:
        m = laminar.Measurements.from_rgl(Path(rgl) / "paper_white_rgb.bsdf", channel="g")
        fit = laminar.fit(m, "exp", grid=GRID)
        cli_fit = cli_fits("--measurements", Path(rgl) / "paper_white_rgb.bsdf", "--channels", "g", "--models", "exp", *GRID_ARGS)
        assert json.loads(fit.to_json())["fits"] == cli_fit



def test_the_simd_path_is_reported_and_gives_the_same_bits(tmp_path):
    import subprocess
    import sys

    assert laminar.simd_path() in ("avx2", "portable")
    script = (
        "import numpy as np, sys; sys.path.insert(0, %r); import laminar_brdf as laminar; "
        "from conftest import geometry, radiance, GRID; g = geometry(90); "
        "values = np.stack([radiance(g, slope=s, a=a, seed=i) for i, (s, a) in enumerate([(0.6, 0.1), (1.6, 0.8)])]); "
        "out = laminar.fit_batch(g, values, 'exp', grid=GRID, quantity='radiance'); "
        "print(laminar.simd_path()); sys.stdout.write(out.tobytes().hex())"
    ) % str(Path(__file__).parent)
    runs = {}
    for path in ("portable", "auto"):
        env = dict(os.environ, LAMINAR_SIMD=path)
        done = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True, check=True)
        name, data = done.stdout.split("\n", 1)
        runs[path] = (name, data)
    assert runs["portable"][0] == "portable"
    assert runs["auto"][0] == laminar.simd_path()
    # The fits' bytes, every field, whichever lanes ran them.
    assert runs["portable"][1] == runs["auto"][1]
    env = dict(os.environ, LAMINAR_SIMD="sse9")
    bad = subprocess.run(
        [sys.executable, "-c", "import laminar_brdf as l; l.simd_path()"], env=env, capture_output=True, text=True
    )
    assert bad.returncode != 0 and 'LAMINAR_SIMD="sse9": expected one of auto, portable, avx2' in bad.stderr
