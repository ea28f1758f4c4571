"""Independent reference: Ngan et al. 2005's Ashikhmin-Shirley as bsdfbenchmark/bbm defines
it (the isotropic specular lobe of Ashikhmin & Shirley 2000 with Schlick's Fresnel of
fresnelReflectance, scaled by albedo; AS's own diffuse replaced by the Lambertian):
    f = kd/pi + albedo (n+1)/(8 pi) NH^n F / (LH max(NL, NV)),
    F = F0 + (1 - F0)(1 - LH)^5,  LH = L.H = V.H."""
import math

import numpy as np


def evaluate(kd, p, L, V):
    L = np.asarray(L, dtype=float)
    V = np.asarray(V, dtype=float)
    n = float(p["sharpness"])
    F0 = float(p["fresnelReflectance"])
    A = p["albedo"]
    A = np.array(A if isinstance(A, (list, tuple)) else [A] * 3, dtype=float)
    out = np.empty((L.shape[0], 3))
    for i in range(L.shape[0]):
        h = L[i] + V[i]
        h = h / math.sqrt(h @ h)
        lh = float(L[i] @ h)
        F = F0 + (1.0 - F0) * (1.0 - lh) ** 5
        spec = (n + 1.0) / (8.0 * math.pi) * h[2] ** n * F / (lh * max(L[i, 2], V[i, 2]))
        out[i] = np.asarray(kd, dtype=float) / math.pi + A * spec
    return out
