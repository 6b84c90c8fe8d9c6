"""Inverse rendering with the Dr.Jit-native BSDF: render a sphere of the exp
model at known parameters, then recover σ/T, β, n and a from that image
alone with ``mi.ad.Adam``, starting from a perturbed guess. The sphere is
lit by three point lights and rendered by Mitsuba's ``direct`` integrator,
so the image (and its gradient) has no Monte Carlo noise beyond pixel
filtering.

σ/T comes back within 1% and β within 0.01; n and a trade off along a
valley one image barely constrains (a higher n with a lower a gives nearly
the same sphere): at a loss 10⁻⁴ of the start, n is within 0.1 and a within
0.05
(python/tests/test_render_native.py states the tolerances it asserts).

    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so \\
        python python/examples/mitsuba_inverse.py
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from mitsuba_sphere import sensor  # noqa: E402

#: The parameters recovered, with the range each is kept in.
RANGES = {"slope": (0.05, 5.0), "beta": (0.0, 1.0), "n": (1.05, 2.5), "a": (0.0, 1.0)}

TRUTH = {"slope": 0.6, "beta": 0.45, "n": 1.45, "a": 0.35}
GUESS = {"slope": 0.9, "beta": 0.3, "n": 1.3, "a": 0.1}


def scene(mi, params, size=48, spp=4):
    """A sphere of the exp model at ``params`` under three point lights
    (key, rim and low), seen head on."""
    bsdf = {"type": "laminar_native", "model": "exp", "sampling": "cosine", **params}
    return mi.load_dict(
        {
            "type": "scene",
            "integrator": {"type": "direct", "emitter_samples": 1, "bsdf_samples": 0},
            "sphere": {"type": "sphere", "bsdf": bsdf},
            "key": {"type": "point", "position": [-3.0, 3.0, 4.0], "intensity": {"type": "rgb", "value": 40.0}},
            "rim": {"type": "point", "position": [4.0, 1.0, -2.0], "intensity": {"type": "rgb", "value": 25.0}},
            "low": {"type": "point", "position": [0.5, -4.0, 1.0], "intensity": {"type": "rgb", "value": 25.0}},
            "sensor": sensor(mi, [0, 0, 5], [0, 0, 0], size, spp, rfilter="box"),
        }
    )


def recover(truth=TRUTH, guess=GUESS, iterations=300, learning_rate=0.05):
    """The parameters recovered from the image of ``truth``, starting at
    ``guess``; the loss at each iteration; seconds taken."""
    import drjit as dr
    import mitsuba as mi

    reference = mi.render(scene(mi, truth), seed=0)
    optimised = scene(mi, guess)
    params = mi.traverse(optimised)
    keys = {name: next(k for k in params.keys() if k.endswith("." + name)) for name in RANGES}
    opt = mi.ad.Adam(lr=learning_rate)
    for name, key in keys.items():
        opt[key] = params[key]
    params.update(opt)
    losses = []
    start = time.perf_counter()
    for it in range(iterations):
        image = mi.render(optimised, params, seed=0)
        loss = dr.mean(dr.square(image - reference), axis=None)
        dr.backward(loss)
        opt.step()
        for name, key in keys.items():
            lo, hi = RANGES[name]
            opt[key] = dr.clip(opt[key], lo, hi)
        params.update(opt)
        losses.append(float(np.array(loss).ravel()[0]))
    found = {name: float(np.array(params[key]).ravel()[0]) for name, key in keys.items()}
    return found, losses, time.perf_counter() - start


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--iterations", type=int, default=300)
    parser.add_argument("--variant", default="llvm_ad_rgb")
    args = parser.parse_args()
    import mitsuba as mi

    mi.set_variant(args.variant)
    import laminar_brdf as laminar
    import laminar_brdf.mitsuba

    laminar.mitsuba.register()
    found, losses, seconds = recover(iterations=args.iterations)
    print(f"{args.iterations} iterations, {seconds:.1f} s; loss {losses[0]:.3e} → {losses[-1]:.3e}")
    print("| parameter | truth | guess | recovered |")
    print("|---|---|---|---|")
    for name in RANGES:
        print(f"| {name} | {TRUTH[name]} | {GUESS[name]} | {found[name]:.4f} |")


if __name__ == "__main__":
    main()
