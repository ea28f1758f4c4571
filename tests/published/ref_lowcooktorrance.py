"""Independent reference for the Cook-Torrance model of Löw et al. 2012's fits as
bsdfbenchmark/bbm evaluates them (`LowCookTorrance`, "directly mirrors the original
Cook-Torrance implementation"):

    f = kd/pi + albedo D G F / (pi NL NV),
    D = exp(-tan^2(theta_h) / m^2) / (m^2 cos^4(theta_h))  (Beckmann without its 1/pi),
    G = min(1, 2 NH NV / VH, 2 NH NL / VH),
    F = unpolarised dielectric Fresnel of index eta at L.H.
"""
import numpy as np


def _fresnel(cos_i, eta):
    # From Snell's law and the s and p amplitudes.
    sin_t = np.sqrt(np.clip(1.0 - cos_i * cos_i, 0.0, None)) / eta
    cos_t = np.sqrt(1.0 - sin_t * sin_t)
    r_s = (cos_i - eta * cos_t) / (cos_i + eta * cos_t)
    r_p = (cos_t - eta * cos_i) / (cos_t + eta * cos_i)
    return 0.5 * (r_s * r_s + r_p * r_p)


def evaluate(kd, p, L, V):
    """(N, 3) RGB values at unit directions L, V of shape (N, 3), Lambertian included."""
    L = np.asarray(L, dtype=float)
    V = np.asarray(V, dtype=float)
    H = L + V
    H = H / np.linalg.norm(H, axis=1)[:, None]
    nl, nv, nh = L[:, 2], V[:, 2], H[:, 2]
    lh = np.sum(L * H, axis=1)
    m = float(p["roughness"])
    tan2 = (H[:, 0] ** 2 + H[:, 1] ** 2) / (nh * nh)
    D = np.exp(-tan2 / (m * m)) / (m * m * nh ** 4)
    G = np.minimum(1.0, np.minimum(2.0 * nh * nv / lh, 2.0 * nh * nl / lh))
    F = _fresnel(lh, float(p["eta"]))
    with np.errstate(divide="ignore", invalid="ignore"):
        spec = D * G * F / (np.pi * nl * nv)
    f = np.asarray(kd, dtype=float)[None, :] / np.pi + spec[:, None] * np.asarray(p["albedo"], dtype=float)[None, :]
    above = (nl > 0.0) & (nv > 0.0)
    return np.where(above[:, None], f, 0.0)
