"""Render a fitted material in Mitsuba 3: a sphere of the fitted model under
a small area light and a dim constant environment, path traced, written as
a PNG.

    laminar fit --data "$CURET_DIR" --samples 49 --models exp --format json --out fits.json
    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so \\
        python python/examples/mitsuba_sphere.py fits.json 49/avg/exp sphere.png

Three comma-separated labels (the r, g and b fits of one sample) give an
RGB material; one gives grey. Needs ``pip install "laminar[mitsuba]"`` and,
for the LLVM variant, Debian's libllvm19 (``--variant scalar_rgb`` runs
without it, slowly).
"""

from __future__ import annotations

import argparse
import time

import numpy as np


def scene_dict(mi, filename, select, size, spp):
    """The scene: a unit sphere of the fitted material, a camera on +z, a
    spherical light up and to the left, a constant environment."""
    bsdf = {"type": "laminar", "filename": filename}
    if select:
        bsdf["select"] = select
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
        "sensor": {
            "type": "perspective",
            "fov": 30,
            "to_world": mi.ScalarTransform4f().look_at(origin=[0, 0, 4.5], target=[0, 0, 0], up=[0, 1, 0]),
            "film": {"type": "hdrfilm", "width": size, "height": size, "rfilter": {"type": "gaussian"}},
            "sampler": {"type": "independent", "sample_count": spp},
        },
    }


def render(filename, select, size=128, spp=64, variant="llvm_ad_rgb"):
    """The rendered image (size × size × 3, linear) and seconds taken."""
    import mitsuba as mi

    mi.set_variant(variant)
    import laminar.mitsuba

    laminar.mitsuba.register()
    scene = mi.load_dict(scene_dict(mi, filename, select, size, spp))
    start = time.perf_counter()
    image = np.array(mi.render(scene))
    return image, time.perf_counter() - start


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("fits", help="fitted-model file (laminar fit --format json)")
    parser.add_argument("select", help="SAMPLE/CHANNEL/MODEL, or three of them separated by commas")
    parser.add_argument("out", help="the PNG to write")
    parser.add_argument("--size", type=int, default=128)
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--variant", default="llvm_ad_rgb")
    args = parser.parse_args()
    image, seconds = render(args.fits, args.select, args.size, args.spp, args.variant)
    import mitsuba as mi

    mi.util.write_bitmap(args.out, image)
    print(f"{args.out}: {args.size} × {args.size}, {args.spp} spp, {seconds:.2f} s ({args.variant})")


if __name__ == "__main__":
    main()
