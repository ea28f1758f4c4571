"""Independent reference: Ngan et al. 2005's Cook-Torrance as bsdfbenchmark/bbm defines it
(NganCookTorrance: microfacet with bbm's Beckmann NDF, normalised by 1/pi by default,
V-groove masking, Schlick Fresnel whose F0 bbm names eta, divided by pi NL NV), plus the
Lambertian:
    f = kd/pi + albedo D G F / (pi NL NV),
    D = exp(-tan^2(theta_h)/m^2) / (pi m^2 cos^4(theta_h)),
    G = min(1, 2 NH NV / VH, 2 NH NL / VH),  F = eta + (1 - eta)(1 - VH)^5."""
import numpy as np


def evaluate(kd, p, L, V):
    L = np.asarray(L, dtype=float)
    V = np.asarray(V, dtype=float)
    alb = np.array(p["albedo"], dtype=float).reshape(-1)
    if alb.size == 1:
        alb = np.repeat(alb, 3)
    m = float(p["roughness"])
    f0 = float(p["eta"])
    H = L + V
    H /= np.sqrt((H * H).sum(axis=1))[:, None]
    nl, nv, nh = L[:, 2], V[:, 2], H[:, 2]
    vh = (V * H).sum(axis=1)
    sin2 = H[:, 0] ** 2 + H[:, 1] ** 2
    D = np.exp(-sin2 / (nh**2 * m**2)) / (np.pi * m**2 * nh**4)
    G = np.minimum.reduce([np.ones_like(nh), 2 * nh * nv / vh, 2 * nh * nl / vh])
    F = f0 + (1 - f0) * (1 - vh) ** 5
    spec = D * G * F / (np.pi * nl * nv)
    return np.asarray(kd, dtype=float)[None, :] / np.pi + spec[:, None] * alb[None, :]
