"""Render a fitted material in Mitsuba 3: a sphere of the fitted model under
a small area light and a dim constant environment, path traced, written as
a PNG.

    laminar fit --data "$CURET_DIR" --samples 49 --models exp --format json --out fits.json
    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so \\
        python python/examples/mitsuba_sphere.py fits.json 49/avg/exp sphere.png

Three comma-separated labels (the r, g and b fits of one sample) give an
RGB material; one gives grey. With ``--material`` the label is a jointly
fitted material's (``sample/model``, from ``laminar fit-joint --fits``): its
channels as red, green and blue, or, in a spectral variant (``--variant
llvm_ad_spectral``, the native plugin), its channels' wavelengths. ``--plugin laminar_native`` draws it with the
Dr.Jit-native BSDF in symbolic mode; ``--compare`` renders with both plugins
in one run and prints their times (the first render, which compiles, and
the fastest of ``--repeat`` after it). Needs ``pip install "laminar-brdf[mitsuba]"`` and,
for the LLVM variant, Debian's libllvm19 (``--variant scalar_rgb`` runs
without it, slowly).
"""

from __future__ import annotations

import argparse
import time

import numpy as np


def sensor(mi, origin, target, size, spp, fov=30, rfilter="gaussian"):
    """A perspective camera at ``origin`` looking at ``target`` (y up), a
    size × size film, ``spp`` independent samples per pixel."""
    return {
        "type": "perspective",
        "fov": fov,
        "to_world": mi.ScalarTransform4f().look_at(origin=origin, target=target, up=[0, 1, 0]),
        "film": {"type": "hdrfilm", "width": size, "height": size, "rfilter": {"type": rfilter}},
        "sampler": {"type": "independent", "sample_count": spp},
    }


def scene_dict(mi, bsdf, size, spp):
    """The scene: a unit sphere of ``bsdf`` (a BSDF dict), a camera on +z, a
    spherical light up and to the left, a constant environment."""
    return {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 3},
        "sphere": {"type": "sphere", "bsdf": bsdf},
        "light": {
            "type": "sphere",
            "center": [-4.0, 4.0, 3.0],
            "radius": 0.5,
            "emitter": {"type": "area", "radiance": {"type": "rgb", "value": 300.0}},
        },
        "environment": {"type": "constant", "radiance": {"type": "rgb", "value": 0.15}},
        "sensor": sensor(mi, [0, 0, 4.5], [0, 0, 0], size, spp),
    }


def fitted_bsdf(filename, select, plugin="laminar", material=False):
    """The BSDF dict of the fit(s) ``select`` of the fitted-model file, or
    of its jointly fitted material ``select`` when ``material``."""
    bsdf = {"type": plugin, "filename": filename}
    if select:
        bsdf["material" if material else "select"] = select
    return bsdf


def render(filename, select, size=128, spp=64, variant="llvm_ad_rgb", plugin="laminar", repeat=0, material=False):
    """The rendered image (size × size × 3, linear) and seconds taken; with
    ``repeat``, also the fastest of that many renders after the first. The
    native plugin renders in symbolic mode, the numpy one in wavefront mode
    (it turns symbolic mode off when loaded)."""
    import drjit as dr
    import mitsuba as mi

    mi.set_variant(variant)
    import laminar_brdf as laminar
    import laminar_brdf.mitsuba

    laminar.mitsuba.register()
    if not variant.startswith("scalar"):
        dr.set_flag(dr.JitFlag.SymbolicLoops, True)
        dr.set_flag(dr.JitFlag.SymbolicCalls, True)
    # The numpy plugin turns symbolic mode off as it loads, on the loading
    # thread only (Dr.Jit's flags are per thread): load it on this one.
    scene = mi.load_dict(
        scene_dict(mi, fitted_bsdf(filename, select, plugin, material), size, spp),
        parallel=plugin == "laminar_native",
    )
    start = time.perf_counter()
    image = np.array(mi.render(scene))
    first = time.perf_counter() - start
    if not repeat:
        return image, first
    times = []
    for i in range(repeat):
        start = time.perf_counter()
        np.array(mi.render(scene, seed=i + 1))
        times.append(time.perf_counter() - start)
    return image, first, min(times)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("fits", help="fitted-model file (laminar fit --format json)")
    parser.add_argument("select", help="SAMPLE/CHANNEL/MODEL, or three of them separated by commas")
    parser.add_argument("out", help="the PNG to write")
    parser.add_argument("--size", type=int, default=128)
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--plugin", default="laminar", choices=["laminar", "laminar_native"])
    parser.add_argument("--compare", action="store_true", help="time both plugins in this run")
    parser.add_argument("--material", action="store_true", help="SELECT is a jointly fitted material (sample/model)")
    parser.add_argument("--repeat", type=int, default=2, help="renders after the first, with --compare")
    args = parser.parse_args()
    import mitsuba as mi

    if args.compare:
        rows = []
        for plugin in ("laminar", "laminar_native"):
            image, first, warm = render(
                args.fits, args.select, args.size, args.spp, args.variant, plugin, args.repeat, args.material
            )
            rows.append((plugin, first, warm))
        print(f"| plugin, {args.size}², {args.spp} spp, {args.variant} | first render (s) | fastest of {args.repeat} after (s) |")
        print("|---|---|---|")
        for plugin, first, warm in rows:
            mode = "symbolic" if plugin == "laminar_native" else "wavefront"
            print(f"| {plugin} ({mode}) | {first:.2f} | {warm:.2f} |")
        print(f"speed-up, warm: {rows[0][2] / rows[1][2]:.1f}×; first: {rows[0][1] / rows[1][1]:.1f}×")
    else:
        image, seconds = render(
            args.fits, args.select, args.size, args.spp, args.variant, args.plugin, material=args.material
        )
        print(f"{args.out}: {args.size} × {args.size}, {args.spp} spp, {seconds:.2f} s ({args.variant}, {args.plugin})")
    mi.util.write_bitmap(args.out, image)


if __name__ == "__main__":
    main()
