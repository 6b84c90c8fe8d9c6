"""Render a fitted texture in Mitsuba 3: the synthetic bidirectional texture
of ``btf_zarr.py`` (SIZE × SIZE texels × 198 directions × 3 channels, the
exp model at smoothly varying parameters plus noise) fitted texel by texel
by ``laminar.xarray.fit``, its parameter maps made the textures of the
Dr.Jit-native BSDF (``laminar.mitsuba_native.textured``), on a square of
ground and a sphere resting on it, lit from behind, path traced, written as
a PNG.

    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so \\
        python python/examples/mitsuba_texture.py texture.png

With ``--fits FILE --sphere LABEL …`` the spheres are fitted models of a
fitted-model file instead, and with ``--material FILE LABEL …`` jointly
fitted materials (``laminar fit-joint --fits FILE``: one material's
channels as red, green and blue; the README's picture: real coloured
materials on the fitted texture). The fit of the 196,608 texels takes a few minutes on two
cores with refinement (``--search-only``: the grid's values, seconds).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

import laminar_brdf as laminar

sys.path.insert(0, str(Path(__file__).resolve().parent))
from mitsuba_sphere import sensor  # noqa: E402


def fitted_texture(size, refine=True):
    """laminar.xarray.fit of the synthetic size × size texture (y, x,
    channel maps) and the seconds it took."""
    import xarray as xr

    import laminar_brdf.xarray

    from btf_cube import cube

    g, values = cube(size, size, k=198, channels=3)
    data = xr.DataArray(
        values.reshape(3, size, size, 198).transpose(1, 2, 0, 3),
        dims=("y", "x", "channel", "measurement"),
        coords={
            "channel": ["r", "g", "b"],
            **{name: ("measurement", g[:, i]) for i, name in enumerate(laminar.xarray.GEOMETRY)},
        },
    )
    start = time.perf_counter()
    fits = laminar.xarray.fit(data, model="exp", quantity="radiance", refine=refine, uncertainty="off")
    return fits, time.perf_counter() - start


def scene_dict(mi, bsdf, size, spp, spheres=()):
    """A square of ``bsdf`` on the ground, lit from behind and above so that
    its highlight shows how the lobe narrows and widens over the texture
    (σ/T grows from left to right), a key light at the front left, a dim
    environment; and resting on the ground a
    sphere of ``bsdf``, or one sphere per BSDF dict of ``spheres``."""
    materials = list(spheres) or [bsdf]
    spacing = 1.1 if len(materials) > 1 else 0.0
    out = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 3},
        "ground": {
            "type": "rectangle",
            "to_world": mi.ScalarTransform4f().rotate([1, 0, 0], -90) @ mi.ScalarTransform4f().scale(1.8),
            "bsdf": bsdf,
        },
        "light": {
            "type": "sphere",
            "center": [0.0, 2.2, -4.0],
            "radius": 0.6,
            "emitter": {"type": "area", "radiance": {"type": "rgb", "value": 6.0}},
        },
        "key": {
            "type": "sphere",
            "center": [-3.0, 3.0, 3.0],
            "radius": 0.4,
            "emitter": {"type": "area", "radiance": {"type": "rgb", "value": 40.0}},
        },
        "environment": {"type": "constant", "radiance": {"type": "rgb", "value": 0.03}},
        "sensor": sensor(mi, [0, 2.0, 3.6], [0, 0.1, -0.2], size, spp, fov=40),
    }
    for i, material in enumerate(materials):
        x = (i - (len(materials) - 1) / 2) * spacing if spacing else 0.75
        out[f"sphere{i}"] = {
            "type": "sphere",
            # The UV seam turned away from the camera.
            "to_world": mi.ScalarTransform4f().translate([x, 0.4, -0.7])
            @ mi.ScalarTransform4f().rotate([0, 1, 0], 90)
            @ mi.ScalarTransform4f().scale(0.4),
            "bsdf": material,
        }
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", help="the PNG to write")
    parser.add_argument("--texels", type=int, default=256, help="texels per side (default 256)")
    parser.add_argument("--size", type=int, default=384, help="image pixels per side")
    parser.add_argument("--spp", type=int, default=128)
    parser.add_argument("--search-only", action="store_true", help="the grid's values, not refined")
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--fits", help="a fitted-model file whose fits --sphere draws")
    parser.add_argument("--sphere", action="append", default=[], help="a label of --fits: one sphere each")
    parser.add_argument(
        "--material",
        nargs=2,
        action="append",
        default=[],
        metavar=("FILE", "LABEL"),
        help="a jointly fitted material (sample/model) of a fitted-model file: one sphere each",
    )
    args = parser.parse_args()
    fits, fit_seconds = fitted_texture(args.texels, refine=not args.search_only)
    print(f"fitted {args.texels}² × 3 texels in {fit_seconds:.1f} s")

    import mitsuba as mi

    mi.set_variant(args.variant)
    import laminar_brdf.mitsuba
    from laminar_brdf.mitsuba_native import textured

    laminar.mitsuba.register()
    spheres = [{"type": "laminar_native", "filename": args.fits, "select": label} for label in args.sphere]
    spheres += [{"type": "laminar_native", "filename": f, "material": label} for f, label in args.material]
    scene = mi.load_dict(scene_dict(mi, textured(fits, nearest=False), args.size, args.spp, spheres))
    start = time.perf_counter()
    image = mi.render(scene)
    mi.util.write_bitmap(args.out, image)
    print(f"{args.out}: {args.size}², {args.spp} spp, {time.perf_counter() - start:.1f} s ({args.variant})")
    slope = np.asarray(fits["slope"].values)
    print(f"σ/T over the texture: {np.nanmin(slope):.2f} to {np.nanmax(slope):.2f} (synthetic truth 0.4 to 3.2)")


if __name__ == "__main__":
    main()
