"""Fits the bundled Cayman paint (a Cornell spectral measurement, to linear sRGB) with
Walter's GGX model and draws measured against fitted values along the plane of incidence,
one panel per incidence angle, to a PNG.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/fit_and_plot.py [OUT.png]
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")  # files only: no display needed
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import brdfit  # noqa: E402

here = os.path.dirname(os.path.abspath(__file__))
data = os.path.join(here, "..", "cornell", "cayman.brdf")
out = sys.argv[1] if len(sys.argv) > 1 else "cayman_walter.png"

samples = brdfit.read(data, rgb=True)
result = brdfit.fit(samples, "walter")
print(result.spec, "rmse_log %.4g" % result.metrics["rmse_log"])
for w in result.warnings:
    print("warning:", w)

theta_i, phi_i, theta_o, phi_o = samples.angles()
dphi = np.radians(phi_o - phi_i)
in_plane = np.abs(np.sin(dphi)) < 0.05  # the plane of incidence
incidences = sorted(set(np.round(theta_i[in_plane]).astype(int)))[:4]

fig, axes = plt.subplots(1, len(incidences), figsize=(4 * len(incidences), 3.5), sharey=True, squeeze=False)
for ax, ti in zip(axes[0], incidences):
    pick = in_plane & (np.abs(theta_i - ti) < 0.5)
    signed = np.where(np.cos(dphi[pick]) < 0, 1.0, -1.0) * theta_o[pick]  # + on the mirror side
    order = np.argsort(signed)
    # The fitted model along the same plane, densely.
    t = np.radians(np.linspace(-89, 89, 357))
    wi = np.tile([np.sin(np.radians(ti)), 0.0, np.cos(np.radians(ti))], (t.size, 1))
    wo = np.stack([-np.sin(t), np.zeros_like(t), np.cos(t)], axis=1)
    fitted = result.model.eval(wi, wo)
    for c, colour in enumerate(("tab:red", "tab:green", "tab:blue")):
        ax.semilogy(signed[order], samples.values[pick][order, c], ".", color=colour, ms=4)
        ax.semilogy(np.degrees(t), fitted[:, c], "-", color=colour, lw=1)
    ax.set_title("theta_i = %d deg" % ti)
    ax.set_xlabel("theta_o (deg, + mirror side)")
axes[0][0].set_ylabel("BRDF (1/sr): dots measured, lines fitted")
fig.suptitle("Cayman paint, %s" % result.spec)
fig.tight_layout()
fig.savefig(out, dpi=100)
print("wrote", out)
