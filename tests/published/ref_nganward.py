"""Independent reference: Ngan et al. 2005's isotropic Ward as bsdfbenchmark/bbm defines
it (NganWard = bbm's ward, isotropic), plus the Lambertian:
    f = kd/pi + albedo exp(-tan^2(theta_h)/a^2) / (4 pi a^2 sqrt(NL NV))."""
import numpy as np


def evaluate(kd, p, L, V):
    L = np.asarray(L, dtype=float)
    V = np.asarray(V, dtype=float)
    albedo = np.broadcast_to(np.asarray(p["albedo"], dtype=float), (3,))
    a = float(p["roughness"])
    H = L + V
    # tan^2(theta_h) = (Hx^2 + Hy^2) / Hz^2, unnormalised H suffices
    tan2 = (H[:, 0] ** 2 + H[:, 1] ** 2) / H[:, 2] ** 2
    lobe = np.exp(-tan2 / (a * a)) / (4.0 * np.pi * a * a * np.sqrt(L[:, 2] * V[:, 2]))
    return np.asarray(kd, dtype=float)[None, :] / np.pi + albedo[None, :] * lobe[:, None]
