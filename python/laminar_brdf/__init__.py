"""laminar: the absorptive scattering model for rough laminar surfaces
(Dahlan & Hancock, ICPR 2016), numpy in and out.

- :func:`evaluate` — every component of the model at arrays of geometries
  and parameters (numpy broadcasting).
- :class:`Measurements` — a measurement set: from arrays, a long-format CSV
  file, a CUReT directory or a MERL file.
- :func:`fit` — the exhaustive grid search of one set; a :class:`FitResult`
  with the parameters, Δ_RMS, χ²/ν, ``predict`` and ``to_json`` (the same
  fitted-model file as ``laminar fit --format json``).
- :func:`compare` — several models fitted to one set and ranked (AICc,
  Akaike weights, K-fold cross-validation).
- :func:`fit_batch` — N sets on one geometry (an N × K array) by the
  shared-geometry batch search; a numpy structured array, one row per set.
- :class:`FittedModel` — a fitted model from a fitted-model file (or a
  :class:`FitResult`): its radiance anywhere and its directional albedo;
  :func:`render` draws a lit sphere of one or three of them, and
  :mod:`laminar.mitsuba` makes them a Mitsuba 3 BSDF.

Every call releases the GIL while Rust works; bad input raises
``ValueError`` naming the parameter, file, line or row.
"""

from __future__ import annotations

import numpy as np

from ._laminar import BATCH_COLUMNS, BATCH_DTYPES, FLAG_BITS, batch_fields, GRID_AXES, MODELS, FitResult, FittedModel, Measurements, paper_angles, render, simd_path
from ._laminar import evaluate as _evaluate
from ._laminar import compare
from ._laminar import fit_joint
from ._laminar import fit as _fit
from ._laminar import fit_batch as _fit_batch

__all__ = [
    "evaluate",
    "fit",
    "compare",
    "fit_joint",
    "fit_batch",
    "Measurements",
    "FitResult",
    "FittedModel",
    "render",
    "paper_angles",
    "simd_path",
    "BATCH_DTYPE",
    "BATCH_DTYPES",
    "batch_dtype",
    "batch_fields",
    "FLAG_BITS",
    "MODELS",
    "GRID_AXES",
]

#: :data:`MODELS` maps each model's name to its ``description``, its
#: ``params`` (in output order), the ``free_params`` a fit estimates and
#: its ``correlation`` (``exp`` or ``gauss`` for the layered models, else
#: None): the library's model descriptor. :data:`GRID_AXES` are the
#: parameters a ``grid`` may set.

#: The fields of :func:`fit_batch`'s result for the tied layered models, in
#: order (:data:`BATCH_COLUMNS`; :func:`batch_fields` gives any layered
#: model's, the untied ones' with σ′/T′'s fields besides).
#:
#: :data:`FLAG_BITS` maps each flag of a parameter to its bit in the
#: ``*_flags`` fields: ``range_edge`` 1 (the estimate is on a face of the
#: box searched), ``domain_bound`` 2 (a bound of the model's domain),
#: ``open_below`` 4 and ``open_above`` 8 (the 95% interval does not close
#: inside the box on that side), ``not_identified`` 16 (the 95% interval
#: spans the whole box).
BATCH_DTYPE = np.dtype([(name, np.float64) for name in BATCH_COLUMNS])


def batch_dtype(model="exp"):
    """The structured dtype of :func:`fit_batch`'s result for ``model`` (a
    layered model): a float64 field per name of :func:`batch_fields`.
    :data:`BATCH_DTYPE` for the tied models; the untied ones (``exp2``,
    ``gauss2``) add ``sub_slope`` and its ``*_lo68`` … ``*_flags``."""
    return np.dtype([(name, np.float64) for name, _ in batch_fields(model)])


def _real(name, x):
    """``x`` as a float64 array of real numbers, or ``ValueError`` naming
    ``name`` (numpy would drop a complex value's imaginary part with a
    warning only)."""
    array = np.asarray(x)
    if array.dtype.kind not in "fiu":
        what = "complex values" if array.dtype.kind == "c" else f"values of type {array.dtype}"
        raise ValueError(f"{name}: {what}; give real numbers (floats or integers)")
    return array.astype(np.float64, copy=False)


def evaluate(model, theta_i, theta_s, phi_s, slope, beta, n, a, sub_slope=None, precision="f64"):
    """Every component of a layered model (``exp``, ``gauss``, ``exp2``,
    ``gauss2``, ``rh-exp``, ``rh-gauss``) at paper-frame angles (radians) and
    parameters, broadcast together like numpy operands. ``sub_slope`` is the
    subsurface slope σ′/T′ of the untied models (``exp2``, ``gauss2``), which
    need it; the others tie it to ``slope`` and refuse it. Returns a dict of
    arrays of the broadcast shape: ``fresnel_in, fresnel_out, absorb_in,
    absorb_out, surface, subsurface, total`` (the raw terms of eqs. 1–14 and
    the eq. 8 total, as ``laminar eval``). ``precision`` is ``"f64"`` or
    ``"f32"``."""
    names = ["theta_i", "theta_s", "phi_s", "slope", "beta", "n", "a"]
    values = [theta_i, theta_s, phi_s, slope, beta, n, a]
    if sub_slope is not None:
        names.append("sub_slope")
        values.append(sub_slope)
    arrays = np.broadcast_arrays(*(_real(name, x) for name, x in zip(names, values)))
    shape = arrays[0].shape
    flat = [np.ascontiguousarray(x.ravel()) for x in arrays]
    sub = flat[7] if sub_slope is not None else None
    out = _evaluate(model, *flat[:7], sub_slope=sub, precision=precision)
    return {name: values.reshape(shape) for name, values in out.items()}


def fit(
    measurements,
    model="exp",
    grid=None,
    refine=True,
    uncertainty="both",
    threads=None,
    objective="free",
    resamples=200,
    seed=0,
    precision="f64",
    noise="given",
    noise_floor=1.0,
):
    """Fits ``model`` (``exp``, ``gauss``, ``exp2``, ``gauss2`` — σ′/T′
    free —, ``rh-exp``, ``rh-gauss``, ``jensen``, ``oren-nayar``) to a
    :class:`Measurements`.

    ``objective``: ``"free"`` (default) minimises ``Σ w (D − c·M)²`` with a
    free amplitude ``c ≥ 0``, ``M`` eq. 8's raw mix (β is eq. 8's, solved
    with ``c`` in closed form), ``w = 1/σ²`` from the measurements'
    uncertainties (else 1), everything inside the box the grid's axes span;
    ``"paper"`` is the paper's max-normalised objective. ``grid`` maps axis
    names (``slope``, ``beta``, ``n``, ``a``) to ``"start:stop:count"``,
    ``"start:stop:count:log"`` or a sequence of values; the objective's
    default grid otherwise. ``refine``: refine the best grid point
    (``FitResult.params`` are then the refined values, ``grid_params`` the
    grid's). ``uncertainty``: ``"profile"`` (68%/95% intervals from the
    profile of the objective), ``"jacobian"`` (standard deviations and
    correlations at the refined optimum), ``"both"`` (the default: with the
    free objective the headline interval is the robust one, the profile's
    calibrated by the sandwich covariance), ``"bootstrap"`` (a pairs
    bootstrap of ``resamples`` refits seeded by ``seed`` as the headline)
    or ``"off"``; see ``FitResult.parameters``. ``threads``: worker threads
    (default: all cores). ``precision``: the arithmetic of the free
    objective's grid stage, ``"f64"`` (default) or ``"f32"`` (the model
    terms in single precision, the sums and everything after in double;
    faster for the Gaussian models' single fits; docs/speed.md).
    ``noise``: how the free objective weighs each measurement, ``"given"``
    (default: the measurements' uncertainties, known; else equal weights),
    ``"equal"``, or ``"relative"`` (σ ∝ the value above a floor of
    ``noise_floor`` times the median positive value, the scale estimated:
    goniometer data; docs/conventions.md §4b)."""
    return _fit(
        measurements, model, grid, refine, uncertainty, threads, objective, resamples, seed, precision, noise, noise_floor
    )


def fit_batch(
    geometry,
    values,
    model="exp",
    grid=None,
    threads=None,
    quantity="brdf",
    refine=True,
    uncertainty="both",
    objective="free",
    precision="f64",
    noise="given",
    noise_floor=1.0,
):
    """Fits a layered ``model`` to every row of ``values`` (N × K) on one
    geometry: ``geometry`` is K × 4 lab-frame angles (radians) ``theta_i,
    phi_i, theta_v, phi_v``. Each row's result equals :func:`fit` on that row
    alone. Returns a structured array of N rows with the fields of
    :func:`batch_dtype` (``model``), float64 each: the batch fields that ``laminar
    fit-batch`` writes and the Dask/xarray results hold (docs/formats.md):
    ``rms, chi2_dof`` of the estimate (refined when ``refine``),
    ``search_rms, rms_grid, measurements``, the free objective's
    ``amplitude`` (of the data divided by ``data_scale``) and
    ``chi2_weighted``, the adequacy ``chi2_p, runs_p,
    lack_of_fit``, ``aicc, bic, rank, weight, cv_rms`` (NaN for one model),
    ``cosine_rms, cube_root``, the Ragheb–Hancock best ``rh_rms, rh_slope,
    rh_beta, rh_n``, then per parameter its value and ``*_lo68, *_hi68,
    *_lo95, *_hi95`` (the headline intervals), ``*_sd`` (Jacobian) and
    ``*_flags`` (the sum of the bits of :data:`FLAG_BITS` that apply, 0:
    none); NaN when not computed. :data:`BATCH_DTYPES` gives each field's
    own dtype (as the Dask results store it).
    ``refine=False, uncertainty="off"`` is the grid search alone, several
    times faster. ``objective``, ``precision``, ``noise`` and
    ``noise_floor`` as in :func:`fit`. The untied models (``exp2``,
    ``gauss2``) have σ′/T′'s fields besides (``sub_slope``, …), after
    σ/T's."""
    # The arrays are checked (real numbers, two dimensions) by name there.
    columns = _fit_batch(
        geometry, values, model, grid, threads, quantity, refine, uncertainty, objective, precision, noise, noise_floor
    )
    dtype = batch_dtype(model)
    out = np.empty(len(columns[dtype.names[0]]), dtype=dtype)
    for name in dtype.names:
        out[name] = columns[name]
    return out
