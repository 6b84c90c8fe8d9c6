"""Fit a long-format CSV file and plot data against model.

    python examples/plot_fit.py MEASUREMENTS.csv [OUT.png]   (needs matplotlib)
"""
import sys

import matplotlib.pyplot as plt
import numpy as np

import laminar_brdf as laminar

path, out = sys.argv[1], (sys.argv[2] if len(sys.argv) > 2 else "fit.png")
m = laminar.Measurements.from_csv(path, quantity="radiance")
result = laminar.fit(m, "exp")
g = np.loadtxt(path, delimiter=",", skiprows=1)
data = g[:, 4] / g[:, 4].max()
model = result.predict(g[:, 0], g[:, 1], g[:, 2], g[:, 3])
plt.scatter(data, model, s=8)
plt.plot([0, 1], [0, 1], "k--", lw=1, label="1:1")
plt.xlabel("measured radiance / max (D)")
plt.ylabel("model prediction (P)")
p = result.params
plt.title(f"exp: σ/T={p['slope']:.2f} β={p['beta']:.2f} n={p['n']:.2f} a={p['a']:.2f}, Δ_RMS={result.rms:.3f}")
plt.legend()
plt.savefig(out, dpi=120)
print(result, "->", out)
