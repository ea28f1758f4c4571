"""Independent reference: Ngan et al. 2005's Ward-Duer as bsdfbenchmark/bbm defines it
(NganWardDuer = bbm's wardduer, isotropic: NL NV in place of Ward's sqrt(NL NV)), plus
the Lambertian:
    f = kd/pi + albedo exp(-tan^2(theta_h)/a^2) / (4 pi a^2 NL NV)."""
import numpy as np


def evaluate(kd, p, L, V):
    L = np.asarray(L, dtype=float)
    V = np.asarray(V, dtype=float)
    rho = np.asarray(p["albedo"], dtype=float) * np.ones(3)
    alpha = float(p["roughness"])
    h = L + V
    h = h / np.linalg.norm(h, axis=1)[:, None]
    cos_h = h[:, 2]
    tan2 = (1.0 - cos_h * cos_h) / (cos_h * cos_h)
    spec = np.exp(-tan2 / alpha**2) / (4.0 * np.pi * alpha**2 * L[:, 2] * V[:, 2])
    return np.outer(spec, rho) + np.asarray(kd, dtype=float) / np.pi
