"""Independent reference for Löw et al. 2012's microfacet (ABC) model as
bsdfbenchmark/bbm evaluates the published fits (`LowMicrofacetFit`):

    f = kd/pi + A D G F / (pi NL NV),
    D = (1 + B (1 - NH))^-C (unnormalised; A carries the scale),
    G = min(1, 2 NH NV / VH, 2 NH NL / VH) (Torrance-Sparrow V-groove),
    F = unpolarised dielectric Fresnel of index eta at L.H,
the pi being the normalisation of the fits listed in the paper's supplemental material.
"""
import numpy as np


def _fresnel(c, eta):
    # Cook & Torrance's closed form in g = sqrt(eta^2 + c^2 - 1).
    g = np.sqrt(eta * eta + c * c - 1.0)
    a = (g - c) / (g + c)
    b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0)
    return 0.5 * a * a * (1.0 + b * b)


def evaluate(kd, p, L, V):
    """(N, 3) RGB values at unit directions L, V of shape (N, 3), Lambertian included."""
    L = np.asarray(L, dtype=float)
    V = np.asarray(V, dtype=float)
    H = L + V
    H = H / np.linalg.norm(H, axis=1)[:, None]
    nl, nv, nh = L[:, 2], V[:, 2], H[:, 2]
    vh = np.sum(V * H, axis=1)
    # 1 - NH as sin^2 / (1 + NH): the literal difference loses digits near the peak
    # where B reaches 8e6.
    one_minus_nh = (H[:, 0] ** 2 + H[:, 1] ** 2) / (1.0 + nh)
    D = (1.0 + float(p["B"]) * one_minus_nh) ** (-float(p["C"]))
    G = np.minimum(1.0, np.minimum(2.0 * nh * nv / vh, 2.0 * nh * nl / vh))
    F = _fresnel(vh, float(p["eta"]))
    with np.errstate(divide="ignore", invalid="ignore"):
        spec = D * G * F / (np.pi * nl * nv)
    f = np.asarray(kd, dtype=float)[None, :] / np.pi + spec[:, None] * np.asarray(p["A"], dtype=float)[None, :]
    above = (nl > 0.0) & (nv > 0.0)
    return np.where(above[:, None], f, 0.0)
