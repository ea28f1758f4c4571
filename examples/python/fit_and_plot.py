"""Fits the bundled Cayman paint (a Cornell spectral measurement: 31 bands, 400 to 700 nm)
with Walter's GGX model and draws measured against fitted values along the plane of
incidence, one panel per incidence angle (the four lowest, 10 to 40 degrees), to a PNG.

What it draws. The three channels are the paint's mean reflectance over 600-700 nm (red),
500-600 nm (green) and 400-500 nm (blue): `rgb_bands=True`. Dots are the measured samples
lying in the plane of incidence (within 3 degrees of it) at that incidence; the x axis is
theta_o, positive on the mirror side. Lines are the fitted model along the same plane.
The y axis is logarithmic: the highlight is hundreds of times the diffuse level.

Why band means and not sRGB (`rgb=True`): this paint's colour lies outside the sRGB
gamut, so its linear sRGB red is negative at almost every sample (1394 of 1439). A log
axis cannot draw a negative value, and a fit (a BRDF is never negative) puts the red
diffuse colour at its bound, 0, so the red line would lie far below the others. Band
means are reflectances, never negative: every dot is drawn, and each channel has a
fit of its own. The script says how many dots it drew and how many a log axis hides.

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

samples = brdfit.read(data, rgb_bands=True)
result = brdfit.fit(samples, "walter")
print(result.spec, "rmse_log %.4g" % result.metrics["rmse_log"])
for w in result.warnings:
    print("warning:", w)

theta_i, phi_i, theta_o, phi_o = samples.angles()
dphi = np.radians(phi_o - phi_i)
in_plane = np.abs(np.sin(dphi)) < 0.05  # the plane of incidence, within 3 degrees
incidences = sorted(set(np.round(theta_i[in_plane]).astype(int)))[:4]
channels = (("tab:red", "600-700 nm"), ("tab:green", "500-600 nm"), ("tab:blue", "400-500 nm"))

drawn = hidden = 0
fig, axes = plt.subplots(1, len(incidences), figsize=(4 * len(incidences), 3.5), sharey=True, squeeze=False)
for ax, ti in zip(axes[0], incidences):
    pick = in_plane & (np.abs(theta_i - ti) < 0.5)
    signed = np.where(np.cos(dphi[pick]) < 0, 1.0, -1.0) * theta_o[pick]  # + on the mirror side
    order = np.argsort(signed)
    measured = samples.values[pick][order]
    # The fitted model along the same plane, densely: one light direction with every view.
    t = np.radians(np.linspace(-89, 89, 357))
    wi = [np.sin(np.radians(ti)), 0.0, np.cos(np.radians(ti))]
    wo = np.stack([-np.sin(t), np.zeros_like(t), np.cos(t)], axis=1)
    fitted = result.model.eval(wi, wo)
    for c, (color, band) in enumerate(channels):
        ax.semilogy(signed[order], measured[:, c], ".", color=color, ms=4)
        ax.semilogy(np.degrees(t), fitted[:, c], "-", color=color, lw=1, label=band)
    drawn += measured.shape[0]
    hidden += int(np.sum(measured <= 0))
    ax.set_title("theta_i = %d deg" % ti)
    ax.set_xlabel("theta_o (deg, + mirror side)")
axes[0][0].set_ylabel("BRDF (1/sr): dots measured, lines fitted")
axes[0][-1].legend(fontsize="small")
fig.suptitle("Cayman paint, band means, %s" % result.spec)
fig.tight_layout()
fig.savefig(out, dpi=100)
print("measured points drawn: %d per channel, %d hidden (<= 0, off a log axis)" % (drawn, hidden))
print("wrote", out)
