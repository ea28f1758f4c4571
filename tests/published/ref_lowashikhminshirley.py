"""Independent reference for the Ashikhmin-Shirley model of Löw et al. 2012's fits as
bsdfbenchmark/bbm evaluates them (`LowAshikhminShirley`: Ashikhmin & Shirley's isotropic
specular lobe with Cook-Torrance's Fresnel of an index of refraction, scaled by an
albedo, beside a plain Lambertian, not A-S's coupled diffuse):

    f = kd/pi + albedo (n + 1) / (8 pi) NH^n F / (LH max(NL, NV)),
    F = unpolarised dielectric Fresnel of index `fresnelReflectance` at L.H.

`fresnelReflectance` is an index of refraction, not a reflectance: bbm builds this model
with fresnel::cook over ior::ior, its values (1.08 to 10.1) are impossible as
reflectances, and they match the same materials' Cook-Torrance eta (aluminium, E1: 9.800
against 9.806).
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
    n = float(p["sharpness"])
    F = _fresnel(lh, float(p["fresnelReflectance"]))
    spec = (n + 1.0) / (8.0 * np.pi) * nh ** n * F / (lh * np.maximum(nl, nv))
    f = np.asarray(kd, dtype=float)[None, :] / np.pi + spec[:, None] * np.asarray(p["albedo"], dtype=float)[None, :]
    above = (nl > 0.0) & (nv > 0.0)
    return np.where(above[:, None], f, 0.0)
