"""A laminar fitted model as a Dr.Jit-native Mitsuba 3 BSDF: the plugin type
``"laminar_native"`` (registered by :func:`laminar.mitsuba.register`).

Eqs. 1–14 and eq. 8 are written here in Dr.Jit operations, so the BSDF runs
inside Mitsuba's kernels: in symbolic (megakernel) mode on the JIT variants,
on ``scalar_rgb``, and with automatic differentiation through every
parameter. The model's parameters are ``mi.Color3f`` members (one value per
channel: grey, or the r, g and b fits of a sample), exposed by ``traverse``
as differentiable and opaque, so changing one does not recompile a kernel.

The formulas follow the Rust core (``core/src/surface.rs``,
``subsurface.rs``, ``fresnel.rs``, ``absorption.rs``; docs/conventions.md
§1–§3) written on directions rather than angles. In Mitsuba's local frame
the light is along ``wo`` and the viewer along ``si.wi``, so with
``h = wi + wo`` (unnormalised):

- cos θi = ``wo.z``, cos θs = ``wi.z``, v_xy² = ``h.x² + h.y²`` and
  v_z = −(cos θi + cos θs) (the paper's eq. 2 with its sign corrected,
  conventions §1), each exact up to the directions' own rounding;
- ``L^sf = cos θi / v_z² · shape(v_xy² / (v_z² (σ/T)²))`` with
  ``shape(x) = exp(−x/4)`` (Gaussian, eq. 1) or ``(1 + x)^(−3/2)``
  (exponential, eq. 2);
- ``L^sb`` the same at the refracted cosines ``sqrt(n² − 1 + cos²)/n`` and
  ``v_xy² / n²`` (eqs. 3, 4), with the subsurface's own roughness σ′/T′
  (``sub_slope``) for the untied models (``exp2``, ``gauss2``) and σ/T for
  the tied ones, times the Fresnel transmittances in and out
  (eqs. 6, 7), the solid angle ``cos θi / (n² cos θi′)`` (eq. 5) and the
  absorption ``(1 − a cos² θi)(1 − a cos² θs)`` (eqs. 10–13);
- radiance ``f · cos θ_light = scale · (β L^sb + (1 − β) L^sf)`` (eq. 8),
  ``β`` and ``scale`` the fitted model's eq. 8 form
  (:attr:`laminar.FittedModel.eq8`: the free objective's β and amplitude
  times the data's scale).

Sampling follows the fitted lobe: a table of the radiance over (cos θ of the
light, the relative azimuth) for 32 viewer angles, sampled by
``mi.MarginalContinuous2D1`` (linear interpolation in the table and the
viewer's angle), mixed with the cosine lobe (:data:`LOBE_SHARE` of the
samples from the table), so the pdf is exact, never zero where f > 0, and
close to f where the table resolves the lobe. The table is rebuilt when a
parameter changes, from the values without their gradients. Property
``sampling``: ``"lobe"`` (the default) or ``"cosine"`` (the cosine lobe
alone).

In a spectral variant (``scalar_spectral``, ``llvm_ad_spectral``, …) the
BSDF draws a material fitted per wavelength (``filename`` and
``material``, its channels named by a wavelength: ``450nm``, ``532``):
each parameter an ``irregular`` spectrum over the channels' wavelengths,
linear between them and held at the end values out to Mitsuba's range,
evaluated at the wavelengths each ray carries.

Properties: ``filename`` with ``select`` or ``material`` as the
``"laminar"`` plugin (a fitted-model file: one label or three, or a
jointly fitted material's channels as red, green and blue), or ``model``
(``exp``, ``gauss``, ``exp2``, ``gauss2``, ``rh-exp``, ``rh-gauss``) with
its parameters (``slope``, ``sub_slope`` for the untied two, ``beta``,
``n``, ``a``) and ``amplitude``, or ``correlation`` (``exp``, ``gauss``)
with ``slope``, ``beta`` (eq. 8's), ``n``, ``a``, ``scale`` and, for the
untied model, ``sub_slope``, each a float or a texture (:func:`textured`
makes them from a fitted texture's maps; the lobe table then follows the
maps' means). Parameters (``mi.traverse``): ``slope``, ``beta``, ``n``,
``a``, ``scale``, and ``sub_slope`` when the model is untied. The
baselines (Jensen, Oren–Nayar) are drawn by the ``"laminar"`` plugin
only.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import laminar_brdf as laminar

if TYPE_CHECKING:
    import xarray

#: The plugin type name.
PLUGIN = "laminar_native"

#: The parameters ``traverse`` exposes, in order, for the tied models.
PARAMETERS = ("slope", "beta", "n", "a", "scale")

#: The untied models' parameters: σ′/T′ (``sub_slope``) besides.
UNTIED_PARAMETERS = PARAMETERS + ("sub_slope",)

#: The share of samples drawn from the lobe's table (the rest from the
#: cosine lobe).
LOBE_SHARE = 0.8

#: The table's resolution: viewer angles (cos θ from :data:`VIEW_MIN` to 1),
#: light cos θ (0 to 1), relative azimuth (−π to π).
TABLE = (32, 64, 128)

#: The smallest viewer cos θ of the table (the sampling clamps to it).
VIEW_MIN = 0.01


def channel_wavelengths(models):
    """The wavelength (nm) each of ``models`` (a material's channels) is
    named by: its channel's leading number (``450nm``, ``532``), as
    ``laminar fit-joint --plot`` reads it; ValueError naming a channel that
    has none, or two channels of one wavelength."""
    import re

    out = []
    for m in models:
        channel = m.label.rsplit("/", 2)[-2]
        found = re.match(r"\d+(\.\d+)?", channel)
        if not found or float(found.group()) <= 0:
            raise ValueError(
                f"{m.label}: channel {channel!r} is not named by a wavelength (450nm, 532, ...); "
                "a spectral variant draws materials fitted per wavelength"
            )
        out.append(float(found.group()))
    if len(set(out)) != len(out):
        raise ValueError(f"the material's channels name a wavelength twice: {sorted(out)}")
    return out


def spectrum(mi, wavelengths, values):
    """An ``irregular`` spectrum of ``values`` at ``wavelengths`` (nm, any
    order), linear between them and held at the end values out to
    Mitsuba's range (``MI_CIE_MIN`` to ``MI_CIE_MAX``, 360–830 nm)."""
    pairs = sorted(zip(wavelengths, values))
    lo, hi = float(mi.MI_CIE_MIN), float(mi.MI_CIE_MAX)
    if pairs[0][0] > lo:
        pairs.insert(0, (lo, pairs[0][1]))
    if pairs[-1][0] < hi:
        pairs.append((hi, pairs[-1][1]))
    return mi.load_dict(
        {
            "type": "irregular",
            "wavelengths": ", ".join(repr(float(w)) for w, _ in pairs),
            "values": ", ".join(repr(float(v)) for _, v in pairs),
        }
    )


def model_name(gaussian, untied):
    """The library's name of the layered model of a correlation, tied or
    untied, from the models' descriptor (:data:`laminar.MODELS`)."""
    correlation = "gauss" if gaussian else "exp"
    for name, d in laminar.MODELS.items():
        free_a = "a" in d["free_params"]
        if d["correlation"] == correlation and free_a and ("sub_slope" in d["params"]) == untied:
            return name
    raise ValueError(f"no {'untied' if untied else 'tied'} {correlation} model in laminar.MODELS")


def eq8_forms(models):
    """The eq. 8 forms (:attr:`laminar.FittedModel.eq8`) of ``models`` (one
    or three), all of one correlation and all tied or all untied (a tied
    form gets no ``sub_slope``); ValueError naming the model otherwise."""
    forms = []
    for m in models:
        form = m.eq8
        if form is None:
            raise ValueError(
                f"{m.label}: the native BSDF draws the layered models (exp, gauss and their rh- variants); "
                f"{m.model} is drawn by the 'laminar' plugin"
            )
        forms.append(form)
    if len({f["correlation"] for f in forms}) != 1:
        raise ValueError("select: the channels' fits use different correlations; the native BSDF needs one")
    if len({"sub_slope" in f for f in forms}) != 1:
        raise ValueError("select: some channels' fits are untied (σ′/T′ of their own) and some tied; give one kind")
    if len(forms) == 1:
        forms *= 3
    return forms


def _shape(x, gaussian):
    """The correlation's falloff: ``exp(−x/4)`` (eq. 1) or ``(1 + x)^(−3/2)``
    (eq. 2)."""
    import drjit as dr

    if gaussian:
        return dr.exp(-0.25 * x)
    y = dr.rcp(1.0 + x)
    return y * dr.sqrt(y)


def _lobe(cos_i, cos_s, vxy2, inv_slope2, gaussian):
    """``cos θi / v_z² · shape(v_xy² (T/σ)² / v_z²)`` (eqs. 1, 2), 0 where
    v_z = 0."""
    import drjit as dr

    sz = cos_i + cos_s
    vz2 = sz * sz
    lit = vz2 > 0
    safe = dr.select(lit, vz2, 1.0)
    value = cos_i / safe * _shape(vxy2 / safe * inv_slope2, gaussian)
    return dr.select(lit, value, 0.0)


def _transmittance(cos_i, cos_t, r):
    """Unpolarised Fresnel transmittance (eqs. 6, 7) from the cosines of the
    incident and refracted angles, as ``laminar_brdf_core::fresnel_pair``: the
    smaller of reflectance and transmittance computed directly, the other
    as its complement. At ``r = 1`` there is no interface: everything is
    transmitted, also where a grazing cosine's square flushes to zero in
    f32 (``(r − 1)(r + 1)/s²`` would be 0/0 there); the denominators are
    made safe before dividing, so that no NaN reaches a gradient either."""
    import drjit as dr

    s_den = cos_i + r * cos_t
    p_den = r * cos_i + cos_t
    s2, p2 = s_den * s_den, p_den * p_den
    r2 = r * r
    r2m1 = (r - 1.0) * (r + 1.0)
    interface = (r2m1 != 0) & (s2 > 0) & (p2 > 0)
    s2 = dr.select(interface, s2, 1.0)
    p2 = dr.select(interface, p2, 1.0)
    rs = r2m1 / s2
    rp = r2m1 * ((r2 + 1.0) * (cos_i * cos_i) - 1.0) / (r2 * p2)
    normal = (r - 1.0) / (r + 1.0)
    f = dr.select(cos_i == 1.0, normal * normal, 0.5 * (rs * rs + rp * rp))
    t = 2.0 * r * cos_i * cos_t * (dr.rcp(s2) + dr.rcp(p2))
    t = dr.minimum(dr.select(f <= t, 1.0 - f, t), 1.0)
    # No interface (r = 1), or cosines too small for their squares: all of
    # it through at r = 1, none at a grazing interface.
    t = dr.select(interface, t, dr.select(r2m1 == 0, 1.0, 0.0))
    return dr.select(cos_i > 0, t, 0.0)


def radiance(wi, wo, slope, beta, n, a, scale, gaussian, sub_slope=None):
    """The fitted radiance ``f · cos θ_light`` (eq. 8) at viewer ``wi`` and
    light ``wo`` (local frame), per channel of the parameters; 0 unless both
    are above the surface. ``sub_slope`` is the subsurface's σ′/T′ (eqs.
    3–4) of an untied model; None ties it to ``slope``."""
    import drjit as dr

    cos_i, cos_s = wo.z, wi.z
    up = (cos_i > 0) & (cos_s > 0)
    cos_i, cos_s = dr.maximum(cos_i, 0.0), dr.maximum(cos_s, 0.0)
    hx, hy = wi.x + wo.x, wi.y + wo.y
    vxy2 = hx * hx + hy * hy
    inv_slope2 = dr.rcp(slope * slope)
    surface = _lobe(cos_i, cos_s, vxy2, inv_slope2, gaussian)
    n2 = n * n
    # Refraction into the layer (eq. 7): cos θ′ = sqrt(n² − 1 + cos² θ)/n
    # (safe_sqrt: no infinite derivative where the sum is 0, at n = 1 and a
    # cosine whose square flushes to zero).
    cos_it = dr.safe_sqrt((n - 1.0) * (n + 1.0) + cos_i * cos_i) / n
    cos_st = dr.safe_sqrt((n - 1.0) * (n + 1.0) + cos_s * cos_s) / n
    inv_sub_slope2 = inv_slope2 if sub_slope is None else dr.rcp(sub_slope * sub_slope)
    base = _lobe(cos_it, cos_st, vxy2 / n2, inv_sub_slope2, gaussian)
    # cos θi/(n² cos θi′) (eq. 5); at n = 1 it is 1, also where a grazing
    # cos θi′ flushes to zero in f32 (the denominator made safe first).
    refracted = n2 * cos_it
    solid_angle = dr.select(refracted > 0, cos_i / dr.select(refracted > 0, refracted, 1.0), dr.rcp(n2))
    sin2_i = dr.clip(wo.x * wo.x + wo.y * wo.y, 0.0, 1.0)
    sin2_s = dr.clip(wi.x * wi.x + wi.y * wi.y, 0.0, 1.0)
    absorption = ((1.0 - a) + a * sin2_i) * ((1.0 - a) + a * sin2_s)
    subsurface = base * _transmittance(cos_i, cos_it, n) * _transmittance(cos_s, cos_st, n) * solid_angle * absorption
    value = scale * (beta * subsurface + (1.0 - beta) * surface)
    return dr.select(up, value, 0.0)


def _light(u, cos_view, phi_view):
    """The light direction of table coordinates ``u`` (x: the paper's φs
    over [−π, π], y: the light's cos θ) for a viewer at azimuth
    ``phi_view``: φ_light = φ_view − φs − π (conventions §1)."""
    import drjit as dr
    import mitsuba as mi

    phi_s = (2.0 * u.x - 1.0) * dr.pi
    cos_t = u.y
    sin_t = dr.safe_sqrt(1.0 - cos_t * cos_t)
    s, c = dr.sincos(phi_view - phi_s - dr.pi)
    return mi.Vector3f(sin_t * c, sin_t * s, cos_t)


def _table_coordinates(wi, wo):
    """The table coordinates (φs over [−π, π] to [0, 1], cos θ) of light
    ``wo`` for viewer ``wi``."""
    import drjit as dr
    import mitsuba as mi

    phi = dr.atan2(wi.y, wi.x) - dr.atan2(wo.y, wo.x) - dr.pi
    phi = phi - dr.two_pi * dr.floor((phi + dr.pi) / dr.two_pi)
    return mi.Point2f(dr.clip((phi + dr.pi) / dr.two_pi, 0.0, 1.0), dr.clip(wo.z, 0.0, 1.0))


def lobe_table(values, gaussian):
    """The radiance (channel mean) on the :data:`TABLE` grid, computed by
    the library from the parameters ``values`` (``name → three floats``;
    with ``sub_slope``, the untied model), as
    float32 ``(views, cos θ, φs)``, each view's row floored at 10⁻⁴ of its
    mean so that every row is a distribution; and the views' cos θ."""
    import numpy as np

    views, rows, cols = TABLE
    cos_view = np.linspace(VIEW_MIN, 1.0, views)
    v, y, x = np.meshgrid(cos_view, np.linspace(0.0, 1.0, rows), np.linspace(0.0, 1.0, cols), indexing="ij")
    theta_i, theta_s = np.arccos(np.ravel(y)), np.arccos(np.ravel(v))
    phi_s = (2.0 * np.ravel(x) - 1.0) * np.pi
    shape = _shape_parameters(values)
    model = model_name(gaussian, "sub_slope" in shape)
    total = np.zeros(theta_i.size)
    for c in range(3):
        params = {p: values[p][c] for p in shape}
        fitted = laminar.FittedModel.from_params(model, params, amplitude=values["scale"][c])
        total += fitted.radiance(theta_i, theta_s, phi_s)
    table = total.reshape(views, rows, cols) / 3.0
    floor = 1e-4 * table.mean(axis=(1, 2), keepdims=True) + 1e-30
    return np.maximum(table, floor).astype(np.float32), cos_view


#: The layered models' parameters, in the library's order: the untied
#: models' (σ′/T′ besides), from the models' descriptor.
LAYERED_PARAMETERS = tuple(max((d["params"] for d in laminar.MODELS.values() if d["correlation"]), key=len))


def _shape_parameters(values):
    """The model's parameters among ``values``' names (all but ``scale``),
    in the library's order."""
    return [p for p in LAYERED_PARAMETERS if p in values]


def check_values(values, gaussian):
    """Refuses parameter values outside the model's domain: ``values`` maps
    each of :data:`PARAMETERS` (and ``sub_slope``, for the untied model) to
    every value it takes (a colour's channels,
    or every texel of a texture's channels). Each must be a number, ``scale``
    at least 0, and the smallest and the largest of each of the others
    inside the library's domain of that parameter (each domain is an
    interval, so then every value is): a ``ValueError`` naming the
    parameter and the value otherwise."""
    import numpy as np

    for name in values:
        v = np.asarray(values[name], dtype=np.float64).ravel()
        bad = ~np.isfinite(v)
        if bad.any():
            raise ValueError(f"{name}: {int(bad.sum())} of its {v.size} values are not numbers (first: {v[bad][0]})")
    scale = np.asarray(values["scale"], dtype=np.float64)
    if (scale < 0).any():
        raise ValueError(f"scale: {scale.min()} is below 0; the amplitude is at least 0")
    shape = _shape_parameters(values)
    model = model_name(gaussian, "sub_slope" in shape)
    for pick in (np.min, np.max):
        at = {p: float(pick(np.asarray(values[p], dtype=np.float64))) for p in shape}
        laminar.FittedModel.from_params(model, at)


def textured(fits: xarray.Dataset, nearest: bool = True) -> dict[str, object]:
    """The ``"laminar_native"`` BSDF dict of a fitted texture: ``fits`` is
    :func:`laminar.xarray.fit`'s Dataset (free objective, a layered model)
    with dimensions ``y``, ``x`` and optionally ``channel`` (three: r, g,
    b), and every parameter becomes a bitmap texture over the surface's UV:
    ``slope``, ``beta``, ``n``, ``a`` and ``scale = amplitude ·
    data_scale``. Texel ``(y, x)`` is at ``uv = ((x + ½)/W, (y + ½)/H)``. A
    value that is not a number (a fit that did not determine it) takes its
    map's median. Call after ``mi.set_variant``."""
    import mitsuba as mi
    import numpy as np

    model = fits.attrs.get("model")
    if fits.attrs.get("objective") != "free":
        raise ValueError(f"fits: objective {fits.attrs.get('objective')!r}; the maps need the free objective's β")
    correlation = laminar.MODELS.get(model, {}).get("correlation")
    if correlation is None:
        raise ValueError(f"fits: model {model!r}; the native BSDF draws the layered models")
    dims = ("y", "x", "channel") if "channel" in fits.dims else ("y", "x")
    if set(fits["slope"].dims) != set(dims):
        raise ValueError(f"fits: dimensions {fits['slope'].dims}; (y, x) or (y, x, channel) are needed")

    def texture(values):
        values = np.asarray(values, dtype=np.float64)
        if values.ndim == 2:
            values = np.repeat(values[..., None], 3, axis=2)
        if values.shape[2] != 3:
            raise ValueError(f"fits: {values.shape[2]} channels; one or three are needed")
        for c in range(3):
            bad = ~np.isfinite(values[..., c])
            if bad.all():
                raise ValueError("fits: a map with no finite value")
            values[..., c][bad] = np.median(values[..., c][~bad])
        bitmap = mi.Bitmap(np.ascontiguousarray(values, dtype=np.float32))
        return {
            "type": "bitmap",
            "bitmap": bitmap,
            "raw": True,
            "filter_type": "nearest" if nearest else "bilinear",
            "wrap_mode": "clamp",
        }

    maps = {name: fits[name].transpose(*dims).values for name in _shape_parameters(fits)}
    maps["scale"] = (fits["amplitude"] * fits["data_scale"]).transpose(*dims).values
    return {"type": PLUGIN, "correlation": correlation, **{name: texture(v) for name, v in maps.items()}}


def register_native():
    """Registers ``"laminar_native"`` with the current Mitsuba variant (call
    after ``mi.set_variant``; :func:`laminar.mitsuba.register` calls it)."""
    import drjit as dr
    import mitsuba as mi
    import numpy as np

    from laminar_brdf.mitsuba import _check_variant, _eval_pdf, _models, _sample_record, _vanishing_pdf

    _check_variant(mi)

    class LaminarNativeBSDF(mi.BSDF):
        """A layered fitted model (one or three channels), in Dr.Jit."""

        def __init__(self, props):
            mi.BSDF.__init__(self, props)
            self.sampling = str(props["sampling"]) if "sampling" in props else "lobe"
            if self.sampling not in ("lobe", "cosine"):
                raise ValueError(f"sampling: {self.sampling!r}; 'lobe' or 'cosine'")
            if mi.is_spectral and "material" not in props:
                raise ValueError(
                    f"Mitsuba variant {mi.variant()!r}: in a spectral variant the laminar_native BSDF draws a "
                    "material fitted per wavelength (`filename` and `material`, from laminar fit-joint --fits); "
                    "fits, parameters and maps are drawn in the RGB variants"
                )
            if "correlation" in props:
                # Maps: each parameter a float or a texture (textured()).
                correlation = str(props["correlation"])
                if correlation not in ("exp", "gauss"):
                    raise ValueError(f"correlation: {correlation!r}; 'exp' or 'gauss'")
                self.gaussian = correlation == "gauss"
                self.models = []
                self.parameters = UNTIED_PARAMETERS if "sub_slope" in props else PARAMETERS
                for name in self.parameters:
                    if name not in props:
                        raise ValueError(f"the laminar_native BSDF with a correlation needs `{name}`")
                    value = props[name]
                    setattr(self, name, value if isinstance(value, mi.Texture) else mi.Color3f(float(value)))
            else:
                if "filename" in props:
                    select = str(props["select"]) if "select" in props else None
                    material = str(props["material"]) if "material" in props else None
                    if mi.is_spectral:
                        # Every channel: the spectral variant samples wavelengths.
                        if select is not None:
                            raise ValueError("give `select` (fits) or `material` (a joint fit), not both")
                        self.models = laminar.FittedModel.from_material(str(props["filename"]), material or None)
                    else:
                        self.models = _models(str(props["filename"]), select, material)
                elif "model" in props:
                    model = str(props["model"])
                    amplitude = float(props["amplitude"]) if "amplitude" in props else 1.0
                    skip = ("model", "amplitude", "sampling")
                    params = {k: float(props[k]) for k in props.keys() if k not in skip}
                    self.models = [laminar.FittedModel.from_params(model, params, amplitude)]
                else:
                    raise ValueError(
                        "the laminar_native BSDF needs `filename` (a fitted-model file, with `select` or "
                        "`material`), `model` and its parameters, or `correlation` and parameter maps"
                    )
                forms = eq8_forms(self.models)
                self.gaussian = forms[0]["correlation"] == "gauss"
                self.parameters = UNTIED_PARAMETERS if "sub_slope" in forms[0] else PARAMETERS
                key = {"beta": "beta_eq8"}
                if mi.is_spectral:
                    # Each parameter a spectrum over the channels' wavelengths,
                    # linear between them (eval at si.wavelengths).
                    nm = channel_wavelengths(self.models)
                    for name in self.parameters:
                        setattr(self, name, spectrum(mi, nm, [f[key.get(name, name)] for f in forms]))
                else:
                    for name in self.parameters:
                        setattr(self, name, mi.Color3f(*(f[key.get(name, name)] for f in forms)))
            self.parameters_changed([])
            flags = mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide
            self.m_components = [flags]
            self.m_flags = flags

        def _values(self, si):
            """Each parameter at ``si`` by name: its value, or its texture's
            there."""
            out = {}
            for name in self.parameters:
                value = getattr(self, name)
                out[name] = value.eval(si) if isinstance(value, mi.Texture) else value
            return out

        def _radiance(self, si, wo):
            v = self._values(si)
            return radiance(
                si.wi, wo, v["slope"], v["beta"], v["n"], v["a"], v["scale"], self.gaussian, v.get("sub_slope")
            )

        def eval(self, ctx, si, wo, active=True):
            return dr.select(active, self._radiance(si, wo), 0.0)

        def _mixture(self, si, wo):
            """The mixture's pdf of light ``wo`` (solid angle) for ``si.wi``."""
            cosine = mi.warp.square_to_cosine_hemisphere_pdf(wo)
            if self.sampling == "cosine":
                return cosine
            cos_view = dr.maximum(mi.Frame3f.cos_theta(si.wi), VIEW_MIN)
            table = self.table.eval(_table_coordinates(si.wi, wo), [cos_view]) / dr.two_pi
            return LOBE_SHARE * table + (1.0 - LOBE_SHARE) * cosine

        def _pdf(self, si, wo, value):
            """The mixture's pdf, 0 where the radiance ``value`` is 0 (the
            table's floor and the cosine share would put mass there)."""
            return _vanishing_pdf(mi, dr, self._mixture, si, wo, value)

        def pdf(self, ctx, si, wo, active=True):
            return _eval_pdf(dr, self, si, wo, active)[1]

        def eval_pdf(self, ctx, si, wo, active=True):
            return _eval_pdf(dr, self, si, wo, active)

        def sample(self, ctx, si, sample1, sample2, active=True):
            wo = mi.warp.square_to_cosine_hemisphere(sample2)
            if self.sampling == "lobe":
                cos_view = dr.maximum(mi.Frame3f.cos_theta(si.wi), VIEW_MIN)
                u, _ = self.table.sample(sample2, [cos_view])
                from_table = _light(u, cos_view, dr.atan2(si.wi.y, si.wi.x))
                wo = dr.select(sample1 < LOBE_SHARE, from_table, wo)
            return _sample_record(mi, dr, self, si, wo, active)

        def traverse(self, callback):
            for name in self.parameters:
                callback.put(name, getattr(self, name), mi.ParamFlags.Differentiable)

        def parameters_changed(self, keys):
            # Opaque: a kernel reads the values from memory, so a new value
            # runs the kernel already compiled.
            def every(value):
                # Every value the parameter takes: a colour's channels, or
                # every texel of a texture's channels.
                if isinstance(value, mi.Texture):
                    # A bitmap's texels, or a spectrum's values.
                    data = [v for k, v in mi.traverse(value).items() if k.endswith("data") or k == "values"]
                    if len(data) != 1:
                        raise ValueError("a parameter's texture must be a bitmap (its texels are checked)")
                    return np.array(dr.detach(data[0]), dtype=np.float64).ravel()
                dr.make_opaque(value)
                return np.array(dr.detach(value), dtype=np.float64).ravel()

            def host(value, texels):
                # A texture's mean stands for it in the table (any table
                # gives an exact pdf; the mean one follows the lobe).
                if isinstance(value, mi.Texture):
                    return np.full(3, float(np.array(dr.detach(value.mean())).ravel()[0]))
                return texels

            # Every value checked, whichever sampling and however it was
            # set (at load, or through mi.traverse and update()), texel by
            # texel: the table's build is no longer the only check.
            texels = {p: every(getattr(self, p)) for p in self.parameters}
            check_values(texels, self.gaussian)
            values = {p: host(getattr(self, p), texels[p]) for p in self.parameters}
            if self.sampling == "lobe":
                table, views = lobe_table(values, self.gaussian)
                self.table = mi.MarginalContinuous2D1(table, [views.tolist()])

        def to_string(self):
            labels = ", ".join(m.label for m in self.models) or "maps"
            return f"LaminarNativeBSDF[{labels}]"

    mi.register_bsdf(PLUGIN, lambda props: LaminarNativeBSDF(props))
