"""A synthetic bidirectional-texture-like cube: H × W pixels × K geometries
× channels, each pixel made by the exp model at smoothly varying
parameters, plus seeded Gaussian noise. Used by the Dask example and test."""

import numpy as np

import laminar_brdf as laminar


def geometry(k=198):
    """k lab-frame geometries (radians), theta_i, phi_i, theta_v, phi_v."""
    i = np.arange(k) + 0.5
    theta_i = np.radians(5 + 70 * ((i * 0.6180339887) % 1))
    theta_v = np.radians(5 + 70 * ((i * 0.7548776662) % 1))
    phi_v = np.pi * (2 * ((i * 0.5698402910) % 1) - 1) * 0.9
    return np.column_stack([theta_i, np.zeros(k), theta_v, phi_v])


def cube(height=64, width=64, k=198, channels=3, noise=0.01, seed=7):
    """(geometry K × 4, values channels × (H·W) × K)."""
    g = geometry(k)
    paper = np.array([laminar.paper_angles(*row) for row in g])
    y, x = np.mgrid[0:height, 0:width]
    u, v = (x.ravel() + 0.5) / width, (y.ravel() + 0.5) / height
    rng = np.random.default_rng(seed)
    out = np.empty((channels, height * width, k))
    for c in range(channels):
        slope = 0.4 + 2.8 * u
        beta = 0.15 + 0.6 * v
        n = 1.32 + 0.04 * c + 0.08 * u * v
        a = 0.1 + 0.7 * (1 - v) * (0.5 + 0.5 * np.cos(3 * u + c))
        total = laminar.evaluate(
            "exp", paper[:, 0], paper[:, 1], paper[:, 2],
            slope[:, None], beta[:, None], n[:, None], a[:, None],
        )["total"]
        total /= total.max(axis=1, keepdims=True)
        out[c] = total + noise * rng.standard_normal(total.shape)
    return g, out
