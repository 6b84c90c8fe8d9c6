"""Fitted models outside the fit: ``FittedModel`` from a fitted-model file
(its radiance, its albedo, as the CLI gives them), ``render``'s sphere, and
the Mitsuba 3 plugin (``laminar.mitsuba``): ``eval`` against the library,
Mitsuba's own χ² test of its sampling, and a white furnace against the
albedo. The Mitsuba tests need ``mitsuba`` with its LLVM variant
(Debian's libllvm19, ``DRJIT_LIBLLVM_PATH``); they say SKIPPED without it,
and fail instead under ``LAMINAR_REQUIRE_MITSUBA=1`` (``.ci/run``)."""

import os

import numpy as np
import pytest

import laminar_brdf as laminar
from conftest import cli


def synthetic(model, truth, seed):
    """A fit of ``model`` to noisy synthetic BRDF data at 198 spread
    directions, written as a fitted-model file: (FitResult, path's text)."""
    rng = np.random.default_rng(seed)
    ti = rng.uniform(0.05, 1.45, 198)
    tv = rng.uniform(0.05, 1.45, 198)
    pi = rng.uniform(-np.pi, np.pi, 198)
    pv = rng.uniform(-np.pi, np.pi, 198)
    paper = np.array([laminar.paper_angles(*g) for g in zip(ti, pi, tv, pv)])
    total = laminar.evaluate(model, paper[:, 0], paper[:, 1], paper[:, 2], *truth)["total"]
    brdf = total / np.cos(ti) * (1 + 0.01 * rng.standard_normal(198))
    m = laminar.Measurements.from_arrays(ti, pi, tv, pv, brdf, name="synthetic")
    return laminar.fit(m, model, uncertainty="off")


@pytest.fixture(scope="module")
def fits(tmp_path_factory):
    """Fitted-model files of an exp and a gauss fit, and the fits."""
    out = {}
    for model, truth, seed in [("exp", (0.9, 0.4, 1.42, 0.3), 1), ("gauss", (0.5, 0.3, 1.5, 0.1), 2)]:
        fit = synthetic(model, truth, seed)
        path = tmp_path_factory.mktemp(model) / "fit.json"
        path.write_text(fit.to_json())
        out[model] = (fit, path)
    return out


def test_fitted_model_predicts_and_integrates_as_the_cli(fits):
    fit, path = fits["exp"]
    m = laminar.FittedModel.from_file(str(path))
    assert m.label == "synthetic/value/exp" or m.label.endswith("/exp")
    rng = np.random.default_rng(3)
    ti, tv = rng.uniform(0, 1.5, 50), rng.uniform(0, 1.5, 50)
    pi, pv = rng.uniform(-3, 3, 50), rng.uniform(-3, 3, 50)
    paper = np.array([laminar.paper_angles(*g) for g in zip(ti, pi, tv, pv)])
    got = m.radiance(paper[:, 0], paper[:, 1], paper[:, 2])
    want = fit.predict(ti, pi, tv, pv, radiance=True)
    np.testing.assert_array_equal(got, want)
    # The albedo equals `laminar albedo`'s, digit for digit as printed.
    degrees = np.array([0.0, 30.0, 60.0])
    albedo, error = m.albedo(np.radians(degrees))
    rows = cli("albedo", "--fit", path, "--theta-v", "0:60:3").splitlines()[1:]
    assert [float(r.split(",")[1]) for r in rows] == pytest.approx(albedo, rel=1e-9)
    assert np.all(error <= 1e-6 * albedo)
    # The tolerance's rule is the library's, as for `laminar albedo --tolerance`.
    for bad in (0.0, -1.0, 1.0, 1e-300, float("nan")):
        with pytest.raises(ValueError, match="give a relative tolerance from 1e-12"):
            m.albedo(np.array([0.0]), tolerance=bad)
    # The file's own rh- label selects the Ragheb–Hancock best, a bad one names the choices.
    with pytest.raises(ValueError, match="no fit `x/y/z`; the file holds"):
        laminar.FittedModel.from_file(str(path), "x/y/z")
    with pytest.raises(ValueError, match="element 0"):
        m.radiance(np.array([2.0]), np.array([0.1]), np.array([0.0]))


def test_render_draws_a_lit_sphere(fits):
    m = laminar.FittedModel.from_file(str(fits["exp"][1]))
    g = laminar.FittedModel.from_file(str(fits["gauss"][1]))
    radiance, srgb = laminar.render([m, g, m], size=48)
    assert radiance.shape == (48, 48, 3) and srgb.shape == (48, 48, 3) and srgb.dtype == np.uint8
    assert np.all(np.isfinite(radiance)) and np.all(radiance >= 0)
    # The light comes from the upper left.
    assert radiance[14, 14, 0] > radiance[34, 34, 0] > 0
    assert radiance[0, 0, 0] == 0
    with pytest.raises(ValueError, match="one or three models"):
        laminar.render([m, g])


def mitsuba_variant(variant):
    """Mitsuba at ``variant`` with the plugin registered, or a skip (a
    failure under LAMINAR_REQUIRE_MITSUBA=1)."""
    required = os.environ.get("LAMINAR_REQUIRE_MITSUBA") == "1"
    try:
        import mitsuba as mi

        mi.set_variant(variant)
    except Exception as e:  # noqa: BLE001 (any reason it cannot run)
        if required:
            pytest.fail(f"Mitsuba 3 ({variant}) is required but cannot run: {e}")
        pytest.skip(f"Mitsuba 3 ({variant}) is not available: {e}")
    import laminar_brdf.mitsuba

    laminar.mitsuba.register()
    return mi


def directions(n, seed):
    """``n`` random direction pairs in the upper hemisphere (x, y, z arrays)."""
    rng = np.random.default_rng(seed)

    def one():
        z = rng.uniform(0.02, 1.0, n)
        phi = rng.uniform(-np.pi, np.pi, n)
        s = np.sqrt(1 - z * z)
        return s * np.cos(phi), s * np.sin(phi), z

    return one(), one()


@pytest.mark.parametrize("variant", ["llvm_ad_rgb", "scalar_rgb"])
def test_mitsuba_eval_is_the_fitted_radiance(fits, variant):
    mi = mitsuba_variant(variant)
    for model in ("exp", "gauss"):
        fit, path = fits[model]
        bsdf = mi.load_dict({"type": "laminar", "filename": str(path)})
        m = laminar.FittedModel.from_file(str(path))
        (vx, vy, vz), (lx, ly, lz) = directions(200 if variant.startswith("llvm") else 20, 5)
        ctx = mi.BSDFContext()
        if variant.startswith("llvm"):
            si = mi.SurfaceInteraction3f()
            si.wi = mi.Vector3f(vx, vy, vz)
            got = np.array(bsdf.eval(ctx, si, mi.Vector3f(lx, ly, lz)))
            got = got.reshape(3, -1) if got.shape[0] == 3 else got.T
            values = got[0]
            np.testing.assert_array_equal(got[0], got[1])
        else:
            values = []
            for k in range(len(vx)):
                si = mi.SurfaceInteraction3f()
                si.wi = mi.Vector3f(vx[k], vy[k], vz[k])
                values.append(bsdf.eval(ctx, si, mi.Vector3f(lx[k], ly[k], lz[k]))[0])
            values = np.array(values)
        ti, tv = np.arccos(lz), np.arccos(vz)
        phi = np.angle(np.exp(1j * (np.arctan2(vy, vx) - np.arctan2(ly, lx) - np.pi)))
        want = m.radiance(ti, tv, phi)
        np.testing.assert_allclose(values, want, rtol=1e-5)


def test_mitsuba_bsdf_from_a_model_and_parameters():
    mi = mitsuba_variant("scalar_rgb")
    params = {"slope": 0.8, "beta": 0.35, "n": 1.45, "a": 0.2}
    bsdf = mi.load_dict({"type": "laminar", "model": "gauss", "amplitude": 2.0, **params})
    m = laminar.FittedModel.from_params("gauss", params, amplitude=2.0)
    si = mi.SurfaceInteraction3f()
    si.wi = mi.Vector3f(0.3, 0.1, float(np.sqrt(1 - 0.1)))
    wo = mi.Vector3f(-0.5, 0.2, float(np.sqrt(1 - 0.29)))
    got = bsdf.eval(mi.BSDFContext(), si, wo)[0]
    (ti, ts, ps, _) = laminar.mitsuba._paper_angles(si.wi, wo)
    assert got == pytest.approx(m.radiance(ti, ts, ps)[0], rel=1e-6)
    # Eq. 8's raw mix times the amplitude.
    total = laminar.evaluate("gauss", ti, ts, ps, *params.values())["total"]
    assert m.radiance(ti, ts, ps)[0] == pytest.approx(2.0 * total[0], rel=1e-12)
    with pytest.raises(ValueError, match="`rho` is not a parameter of gauss"):
        laminar.FittedModel.from_params("gauss", {**params, "rho": 0.1})
    with pytest.raises(ValueError, match="`a` is missing"):
        laminar.FittedModel.from_params("exp", {"slope": 1.0, "beta": 0.5, "n": 1.4})


def test_mitsuba_sampling_passes_its_chi2_test(fits):
    mi = mitsuba_variant("llvm_ad_rgb")
    from mitsuba.chi2 import BSDFAdapter, ChiSquareTest, SphericalDomain

    p_values = []
    for model in ("exp", "gauss"):
        path = fits[model][1]
        for theta in (0.2, 0.7, 1.2):
            wi = mi.Vector3f(float(np.sin(theta)), 0.0, float(np.cos(theta)))
            sample, pdf = BSDFAdapter("laminar", f'<string name="filename" value="{path}"/>', wi=wi)
            test = ChiSquareTest(domain=SphericalDomain(), sample_func=sample, pdf_func=pdf, sample_dim=3)
            ok = test.run()
            p_values.append((model, theta, test.p_value))
            assert ok, f"{model} at θ = {theta}: {test.messages}"
    print("chi2 p-values:", p_values)


def test_white_furnace_equals_the_albedo(fits):
    """A plane facing the camera under a uniform emitter of radiance 1, one
    bounce: each pixel is ρ(θv = 0) up to Monte Carlo error."""
    mi = mitsuba_variant("llvm_ad_rgb")
    path = fits["exp"][1]
    m = laminar.FittedModel.from_file(str(path))
    albedo = m.albedo(np.array([0.0]))[0][0]
    scene = mi.load_dict(
        {
            "type": "scene",
            "integrator": {"type": "path", "max_depth": 2},
            "emitter": {"type": "constant", "radiance": {"type": "rgb", "value": 1.0}},
            "plane": {"type": "rectangle", "bsdf": {"type": "laminar", "filename": str(path)}},
            "sensor": {
                "type": "orthographic",
                "to_world": mi.ScalarTransform4f().look_at(origin=[0, 0, 5], target=[0, 0, 0], up=[0, 1, 0])
                @ mi.ScalarTransform4f().scale([0.5, 0.5, 1]),
                "film": {"type": "hdrfilm", "width": 16, "height": 16, "rfilter": {"type": "box"}},
                "sampler": {"type": "independent", "sample_count": 256},
            },
        },
        parallel=False,  # the numpy plugin's flags on this thread (laminar.mitsuba)
    )
    image = np.array(mi.render(scene))[..., 0]
    mean = image.mean()
    # Each pixel is an independent 256-sample estimate: the mean's standard error.
    standard_error = image.std(ddof=1) / np.sqrt(image.size)
    print(f"furnace: {mean:.5f} ± {standard_error:.5f} against the albedo {albedo:.5f}")
    assert abs(mean - albedo) < 4 * standard_error + 1e-6, (mean, standard_error, albedo)


@pytest.mark.skipif(not os.environ.get("CURET_DIR"), reason="CURET_DIR is not set")
def test_a_fitted_curet_sample_renders_in_mitsuba(tmp_path):
    """CUReT sample 49, fitted by `laminar fit` into its fitted-model file,
    path traced in Mitsuba (python/examples/mitsuba_sphere.py): finite,
    non-negative, and the sphere lit from the upper left."""
    mitsuba_variant("llvm_ad_rgb")
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "examples"))
    from mitsuba_sphere import render

    path = tmp_path / "fits.json"
    cli("fit", "--data", os.environ["CURET_DIR"], "--samples", 49, "--models", "exp", "--format", "json", "--out", path)
    image, seconds = render(str(path), "49/avg/exp", size=48, spp=32)
    print(f"CUReT 49 in Mitsuba: 48 × 48, 32 spp, {seconds:.2f} s")
    assert image.shape == (48, 48, 3)
    assert np.all(np.isfinite(image)) and np.all(image >= 0)
    lit = image[14:20, 14:20, 0].mean()
    away = image[30:36, 30:36, 0].mean()
    assert lit > 2 * away > 0, (lit, away)


def test_mono_and_polarised_variants_are_refused_by_name():
    """The plugins return three channels, or a spectrum of a material
    fitted per wavelength: a mono or polarised variant is refused at
    register() naming it (both plugins loaded, then ``mi.render`` died with
    ``std::bad_cast``: issue 55, item 8), and the numpy plugin refuses a
    spectral one when a BSDF is loaded."""
    mi = mitsuba_variant("scalar_rgb")
    import laminar_brdf.mitsuba

    tried = 0
    for variant in ("scalar_mono", "llvm_ad_mono", "llvm_ad_spectral_polarized", "scalar_spectral_polarized"):
        if variant not in mi.variants():
            continue
        mi.set_variant(variant)
        with pytest.raises(ValueError, match=f"variant '{variant}'.*RGB variants"):
            laminar.mitsuba.register()
        tried += 1
    assert tried > 0, mi.variants()
    mi = mitsuba_variant("scalar_spectral")
    with pytest.raises(Exception, match="'laminar' plugin draws the RGB variants, not 'scalar_spectral'"):
        mi.load_dict({"type": "laminar", "model": "exp", "slope": 0.5, "beta": 0.3, "n": 1.5, "a": 0.1})
    with pytest.raises(Exception, match="spectral variant the laminar_native BSDF draws a material"):
        mi.load_dict({"type": "laminar_native", "model": "exp", "slope": 0.5, "beta": 0.3, "n": 1.5, "a": 0.1})
    mi.set_variant("scalar_rgb")


def test_a_joint_material_renders_as_one_rgb_bsdf(tmp_path):
    """``laminar fit-joint --fits``: the material's channels as
    ``FittedModel.from_material`` gives them are the file's per-channel
    fits (``from_file`` with ``sample/channel/model``) and the joint fit's
    own predictions; the Mitsuba plugin's ``material`` draws them as red,
    green and blue."""
    from conftest import paint_material

    data, path = paint_material(tmp_path, "exp")
    models = laminar.FittedModel.from_material(str(path))
    assert [m.label for m in models] == ["paint/r/exp", "paint/g/exp", "paint/b/exp"]
    channels = [laminar.Measurements.from_csv(data, quantity="radiance", channel=c) for c in "rgb"]
    joint = laminar.fit_joint(channels, "exp", uncertainty="off", folds=0)
    ti, tv, phi = np.radians([30.0, 50.0]), np.radians([40.0, 20.0]), np.radians([120.0, -60.0])
    for c, m in enumerate(models):
        same = laminar.FittedModel.from_file(str(path), m.label)
        np.testing.assert_array_equal(m.radiance(ti, tv, phi), same.radiance(ti, tv, phi))
        assert m.data_scale == joint["channels"][c]["data_scale"]
    # The absorption differs between the channels, the geometry does not.
    assert len({tuple(m.radiance(ti, tv, phi)) for m in models}) == 3
    with pytest.raises(ValueError, match="no material `paint/gauss`"):
        laminar.FittedModel.from_material(str(path), "paint/gauss")
    mi = mitsuba_variant("scalar_rgb")
    bsdf = mi.load_dict({"type": "laminar", "filename": str(path), "material": "paint/exp"})
    si = mi.SurfaceInteraction3f()
    si.wi = mi.Vector3f(np.sin(tv[0]) * np.cos(phi[0]), np.sin(tv[0]) * np.sin(phi[0]), np.cos(tv[0]))
    wo = mi.Vector3f(np.sin(ti[0]), 0.0, np.cos(ti[0]))
    got = bsdf.eval(mi.BSDFContext(), si, wo)
    (pti, pts, pps, _) = laminar.mitsuba._paper_angles(si.wi, wo)
    want = [m.radiance(pti, pts, pps)[0] for m in models]
    np.testing.assert_allclose([got[0], got[1], got[2]], want, rtol=1e-5)
    assert got[0] != got[2]
    with pytest.raises(Exception, match="not both"):
        mi.load_dict({"type": "laminar", "filename": str(path), "material": "paint/exp", "select": "paint/r/exp"})
