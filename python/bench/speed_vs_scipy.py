"""One laminar fit with its defaults (the free-amplitude objective: grid
stage, refinement, 68%/95% profile intervals and the Jacobian) against the
peer a Python user would pick: a 20-start bounded
``scipy.optimize.least_squares`` fit of the same objective, Σ (D − c·M)²
over (σ/T, β, n, a, c) in the same box, with the model from
``laminar.evaluate``. Both run here, in one process, on CUReT sample 21
(the exp model, K = 198 after the specular exclusion).

Usage: python bench/speed_vs_scipy.py CURET_DIR [repeats]
"""

import math
import sys
import time

import numpy as np
from scipy.optimize import least_squares

import laminar_brdf as laminar


def curet_sample(directory, sample):
    """Lab-frame angles (radians) and BRDF of one CUReT sample, specular
    rows left out (docs/conventions.md §1)."""
    table = np.loadtxt(f"{directory}/table.txt")
    rows = {}
    with open(f"{directory}/abrdf.dat") as f:
        for line in f:
            parts = line.split()
            if parts:
                rows[int(float(parts[0]))] = np.array(parts[1:], dtype=float)
    theta_v, phi_v, theta_i, phi_i = table[:, 1], table[:, 2], table[:, 3], table[:, 4]
    specular = (np.abs(theta_v - theta_i) <= 1e-4) & (np.abs(np.abs(phi_v - phi_i) - math.pi) <= 1e-4)
    keep = ~specular
    return theta_i[keep], phi_i[keep], theta_v[keep], phi_v[keep], rows[sample][keep]


def main():
    directory = sys.argv[1]
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 20
    ti, pi, tv, pv, brdf = curet_sample(directory, 21)
    m = laminar.Measurements.from_arrays(ti, pi, tv, pv, brdf, quantity="brdf", name="21")
    paper = np.array([laminar.paper_angles(*g) for g in zip(ti, pi, tv, pv)])
    data = brdf * np.cos(ti)
    data = data / data.max()
    (slope_lo, slope_hi), (beta_lo, beta_hi), (n_lo, n_hi), (a_lo, a_hi) = (0.02, 20.0), (0.0, 1.0), (1.0, 2.5), (0.0, 1.0)

    laminar.fit(m, "exp")  # warm-up
    start = time.perf_counter()
    for _ in range(repeats):
        ours = laminar.fit(m, "exp")
    laminar_s = (time.perf_counter() - start) / repeats
    ours_sse = float(np.sum((data - ours.predict(ti, pi, tv, pv)) ** 2))

    def residual(x):
        slope, beta, n, a, c = x
        total = laminar.evaluate("exp", paper[:, 0], paper[:, 1], paper[:, 2], slope, beta, n, a)["total"]
        return data - c * total

    rng = np.random.default_rng(21)
    lower = [slope_lo, beta_lo, n_lo, a_lo, 0.0]
    upper = [slope_hi, beta_hi, n_hi, a_hi, np.inf]
    start = time.perf_counter()
    best = math.inf
    evaluations = 0
    for _ in range(20):
        x0 = [
            math.exp(rng.uniform(math.log(slope_lo), math.log(slope_hi))),
            rng.uniform(beta_lo, beta_hi),
            rng.uniform(n_lo, n_hi),
            rng.uniform(a_lo, a_hi),
            1.0,
        ]
        r = least_squares(residual, x0, bounds=(lower, upper), method="trf", x_scale="jac")
        evaluations += r.nfev
        best = min(best, 2.0 * r.cost)
    scipy_s = time.perf_counter() - start

    print(f"laminar.fit (defaults: grid, refinement, profile intervals, Jacobian): {laminar_s * 1e3:.2f} ms per fit, Σ(D−P)² = {ours_sse:.9e}")
    print(f"scipy least_squares, 20 starts (fit only, no intervals): {scipy_s * 1e3:.1f} ms per fit, {evaluations} model evaluations, best Σ(D−P)² = {best:.9e}")
    print(f"ratio: laminar is {scipy_s / laminar_s:.0f}x faster per fit; its objective is {'not above' if ours_sse <= best * (1 + 1e-9) else 'ABOVE'} scipy's best")


if __name__ == "__main__":
    main()
