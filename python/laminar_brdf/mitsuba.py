"""Fitted models as a Mitsuba 3 BSDF: ``laminar.mitsuba.register()`` adds the
plugin type ``"laminar"``.

.. code-block:: python

    import mitsuba as mi
    mi.set_variant("llvm_ad_rgb")      # or "scalar_rgb"
    import laminar_brdf as laminar
    import laminar_brdf.mitsuba
    laminar.mitsuba.register()
    bsdf = mi.load_dict({"type": "laminar", "filename": "fits.json", "select": "49/avg/exp"}, parallel=False)

Properties: ``filename``, a fitted-model file (``laminar fit --format
json``), and ``select``: one label ``sample/channel/model`` (grey), or
three separated by commas (red, green, blue: e.g. the r, g and b fits of
one sample); left out when the file holds one fit. Or ``material``: the
label ``sample/model`` of a jointly fitted material (``laminar fit-joint
--fits``), its channels red, green and blue (or one, grey). Or, without a file,
``model`` (``exp``, ``gauss``, …), its parameters as floats (``slope``,
``beta``, ``n``, ``a``; ``sigma_a``, ``sigma_s``; ``sigma``, ``rho``) and
``amplitude`` (default 1): the grey BSDF ``amplitude · ((1 − β) L^sf + β
L^sb) / cos θ_light`` (:meth:`laminar.FittedModel.from_params`).

In Mitsuba's local frame the light is along ``wo`` and the viewer along
``si.wi``; ``eval`` returns the fitted model's radiance ``f · cos θ_light``
in the fitted data's units (``P · data_scale``, docs/conventions.md §12),
evaluated by the Rust library on whole arrays of directions (one call per
channel per wavefront, no Python loop per ray). Sampling is
cosine-weighted: its pdf is exact and cheap, and the fitted lobes of this
model family are broad (the subsurface term is diffuse-like), so the
variance stays low; a lobe-following mixture is not implemented.

The plugins serve the RGB variants; in a spectral one ``"laminar_native"``
draws a material fitted per wavelength (:mod:`laminar.mitsuba_native`)
and ``"laminar"`` refuses to load.

On the JIT variants the evaluation leaves Dr.Jit for numpy, so a scene
must render in wavefront mode: loading a ``"laminar"`` BSDF turns Dr.Jit's
symbolic loops and calls off, on the thread that loads it only (Dr.Jit's
flags are per thread), so load its scene with ``mi.load_dict(...,
parallel=False)``. Symbolic calls trace every live BSDF, so collect a
``"laminar"`` BSDF (``gc.collect()``) before rendering another scene in
symbolic mode. :func:`register` also adds
``"laminar_native"`` (:mod:`laminar.mitsuba_native`): the layered models in
Dr.Jit itself, for symbolic mode, the CUDA variants and differentiation.
This plugin stays as the reference the native one is tested against.
"""

from __future__ import annotations

import numpy as np

import laminar_brdf as laminar

#: The plugin type name.
PLUGIN = "laminar"


def _models(filename, select, material=None):
    if material is not None:
        if select is not None:
            raise ValueError("give `select` (fits) or `material` (a joint fit), not both")
        models = laminar.FittedModel.from_material(str(filename), material or None)
        if len(models) not in (1, 3):
            raise ValueError(
                f"material {material}: {len(models)} channels; the BSDF draws one (grey) or three (red, green, blue)"
            )
        return models
    labels = [None] if not select else [s.strip() for s in str(select).split(",")]
    if len(labels) not in (1, 3):
        raise ValueError(f"select: {len(labels)} labels; give one (grey) or three (red, green, blue)")
    return [laminar.FittedModel.from_file(str(filename), label) for label in labels]


def _paper_angles(wi, wo):
    """θi, θs, φs (paper frame) of light ``wo`` and viewer ``wi``, local
    frame, as numpy arrays; and where both are above the surface."""
    lx, ly, lz = (np.atleast_1d(np.array(c, dtype=np.float64)) for c in (wo.x, wo.y, wo.z))
    vx, vy, vz = (np.atleast_1d(np.array(c, dtype=np.float64)) for c in (wi.x, wi.y, wi.z))
    lx, ly, lz, vx, vy, vz = np.broadcast_arrays(lx, ly, lz, vx, vy, vz)
    above = (lz > 0) & (vz > 0)
    theta_i = np.arccos(np.clip(lz, 0.0, 1.0))
    theta_s = np.arccos(np.clip(vz, 0.0, 1.0))
    # Lab frame to paper frame: φs = φv − φi − π, wrapped (conventions §1).
    phi = np.arctan2(vy, vx) - np.arctan2(ly, lx) - np.pi
    phi_s = np.angle(np.exp(1j * phi))
    return theta_i, theta_s, phi_s, above


def _check_variant(mi):
    """Refuses a variant the plugins cannot serve: they return three
    channels (``mi.Color3f``) in the RGB variants, and the native one a
    spectrum of a material fitted per wavelength in the (unpolarised)
    spectral variants; a mono variant's ``Spectrum`` has 1 value and a
    polarised one is a matrix (the render died with ``std::bad_cast``
    after loading)."""
    if mi.variant() is None:
        raise RuntimeError("set a Mitsuba variant (mi.set_variant) before laminar.mitsuba.register()")
    if not (mi.variant().endswith("_rgb") or mi.variant().endswith("_spectral")):
        raise ValueError(
            f"Mitsuba variant {mi.variant()!r}: the laminar BSDFs serve the RGB variants "
            "(scalar_rgb, llvm_ad_rgb, cuda_ad_rgb, ...) and, for materials fitted per wavelength, "
            "the spectral ones (scalar_spectral, llvm_ad_spectral, ...), not mono or polarised ones; "
            "set one of those before laminar.mitsuba.register()"
        )


def _vanishing_pdf(mi, dr, mixture, si, wo, value):
    """The sampling pdf ``mixture(si, wo)``, 0 where the radiance ``value``
    is 0 in every channel (underflowed, or below the horizon): sample()
    gives such directions no weight, so the pdf gives them no mass (as
    Mitsuba's microfacet BSDFs do)."""
    up = (mi.Frame3f.cos_theta(si.wi) > 0) & (mi.Frame3f.cos_theta(wo) > 0) & dr.any(value > 0)
    return dr.select(up, mixture(si, wo), 0.0)


def _eval_pdf(dr, bsdf, si, wo, active):
    """``bsdf``'s radiance and pdf of direction ``wo`` (its ``_pdf``)."""
    value = dr.select(active, bsdf._radiance(si, wo), 0.0)
    return value, dr.select(active, bsdf._pdf(si, wo, value), 0.0)


def _sample_record(mi, dr, bsdf, si, wo, active):
    """The BSDF sample of direction ``wo`` and its weight: radiance over
    the pdf ``bsdf._pdf``, none where that pdf is 0."""
    bs = mi.BSDFSample3f()
    bs.wo = wo
    value = bsdf._radiance(si, wo)
    bs.pdf = bsdf._pdf(si, wo, value)
    bs.eta = 1.0
    bs.sampled_type = mi.UInt32(+mi.BSDFFlags.GlossyReflection)
    bs.sampled_component = mi.UInt32(0)
    weight = value / dr.maximum(bs.pdf, 1e-30)
    return bs, dr.select(active & (bs.pdf > 0), weight, 0.0)


def register() -> None:
    """Registers the ``"laminar"`` and ``"laminar_native"`` BSDFs with the
    current Mitsuba variant (call after ``mi.set_variant``)."""
    import drjit as dr
    import mitsuba as mi

    _check_variant(mi)
    scalar = mi.variant().startswith("scalar")

    class LaminarBSDF(mi.BSDF):
        """A laminar fitted model (one or three channels)."""

        def __init__(self, props):
            mi.BSDF.__init__(self, props)
            if mi.is_spectral:
                raise ValueError(
                    f"the 'laminar' plugin draws the RGB variants, not {mi.variant()!r}; in a spectral "
                    "variant draw a material fitted per wavelength with 'laminar_native'"
                )
            if "filename" in props:
                self.filename = str(props["filename"])
                self.select = str(props["select"]) if "select" in props else None
                material = str(props["material"]) if "material" in props else None
                self.models = _models(self.filename, self.select, material)
            elif "model" in props:
                self.filename, self.select = None, None
                model = str(props["model"])
                amplitude = float(props["amplitude"]) if "amplitude" in props else 1.0
                params = {k: float(props[k]) for k in props.keys() if k not in ("model", "amplitude")}
                self.models = [laminar.FittedModel.from_params(model, params, amplitude)]
            else:
                raise ValueError("the laminar BSDF needs `filename` (a fitted-model file) or `model` and its parameters")
            flags = mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide
            self.m_components = [flags]
            self.m_flags = flags
            if not scalar:
                # numpy inside: the scene renders in wavefront mode.
                dr.set_flag(dr.JitFlag.SymbolicLoops, False)
                dr.set_flag(dr.JitFlag.SymbolicCalls, False)

        def _radiance(self, si, wo):
            ti, ts, ps, above = _paper_angles(si.wi, wo)
            channels = []
            for model in self.models:
                values = np.zeros_like(ti)
                if above.any():
                    values[above] = model.radiance(ti[above], ts[above], ps[above])
                channels.append(values)
            if len(channels) == 1:
                channels *= 3
            if scalar:
                return mi.Color3f(*(float(c[0]) for c in channels))
            return mi.Color3f(*(mi.Float(c) for c in channels))

        def eval(self, ctx, si, wo, active=True):
            return dr.select(active, self._radiance(si, wo), 0.0)

        def _pdf(self, si, wo, value):
            """The cosine pdf of ``wo``, 0 where the radiance ``value`` is 0."""
            return _vanishing_pdf(mi, dr, lambda si, wo: mi.warp.square_to_cosine_hemisphere_pdf(wo), si, wo, value)

        def pdf(self, ctx, si, wo, active=True):
            return _eval_pdf(dr, self, si, wo, active)[1]

        def eval_pdf(self, ctx, si, wo, active=True):
            return _eval_pdf(dr, self, si, wo, active)

        def sample(self, ctx, si, sample1, sample2, active=True):
            return _sample_record(mi, dr, self, si, mi.warp.square_to_cosine_hemisphere(sample2), active)

        def traverse(self, callback):
            pass

        def to_string(self):
            labels = ", ".join(m.label for m in self.models)
            return f"LaminarBSDF[{labels}]"

    mi.register_bsdf(PLUGIN, lambda props: LaminarBSDF(props))
    from laminar_brdf.mitsuba_native import register_native

    register_native()
