"""Independent reference for Löw et al. 2012's smooth-surface model as bsdfbenchmark/bbm
evaluates its published fits (`LowSmooth`, the paper's eqs. 10, 12 and 14):

    f = kd/pi + A S(|Dp|) Q(theta_d),  S(f) = (1 + B f^2)^-C,
    Dp = projection of V minus projection of the mirror of L = L_xy + V_xy,
    cos(theta_d) = sqrt(1 - |L_xy - V_xy|^2 / 4),
    Q = unpolarised Fresnel reflectance of a dielectric of index eta.
"""
import numpy as np


def _fresnel(cos_i, eta):
    # From Snell's law and the s and p amplitudes (not the Cook-Torrance g form).
    sin_t = np.sqrt(np.clip(1.0 - cos_i * cos_i, 0.0, None)) / eta
    cos_t = np.sqrt(1.0 - sin_t * sin_t)
    r_s = (cos_i - eta * cos_t) / (cos_i + eta * cos_t)
    r_p = (cos_t - eta * cos_i) / (cos_t + eta * cos_i)
    return 0.5 * (r_s * r_s + r_p * r_p)


def evaluate(kd, p, L, V):
    """(N, 3) RGB values at unit directions L, V of shape (N, 3), Lambertian included."""
    L = np.asarray(L, dtype=float)
    V = np.asarray(V, dtype=float)
    mirror_l = L * np.array([-1.0, -1.0, 1.0])
    dp2 = np.sum((V[:, :2] - mirror_l[:, :2]) ** 2, axis=1)
    chord2 = np.sum((L[:, :2] - V[:, :2]) ** 2, axis=1)
    cos_d = np.sqrt(np.clip(1.0 - 0.25 * chord2, 0.0, None))
    S = (1.0 + float(p["B"]) * dp2) ** (-float(p["C"]))
    Q = _fresnel(cos_d, float(p["eta"]))
    lobe = (S * Q)[:, None] * np.asarray(p["A"], dtype=float)[None, :]
    f = np.asarray(kd, dtype=float)[None, :] / np.pi + lobe
    above = (L[:, 2] > 0.0) & (V[:, 2] > 0.0)
    return np.where(above[:, None], f, 0.0)
