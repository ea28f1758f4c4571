"""Independent reference: Ngan et al. 2005's "Blinn-Phong" plus the Lambertian, in either
reading of the published numbers (docs/models.md, "Published fits"):
- "half" (brdfit's choice): f = kd/pi + albedo (n+2)/(2 pi) NH^n;
- "mirror" (what bsdfbenchmark/bbm evaluates, its Phong):
  f = kd/pi + albedo (n+2)/(2 pi) max(R.V, 0)^n with R = 2 NL N - L."""
import numpy as np


def evaluate(kd, p, L, V, reading="half"):
    L = np.asarray(L, dtype=float)
    V = np.asarray(V, dtype=float)
    n = float(p["sharpness"])
    albedo = np.asarray(p["albedo"], dtype=float) * np.ones(3)
    if reading == "half":
        H = (L + V) / np.linalg.norm(L + V, axis=1, keepdims=True)
        c = H[:, 2]
    elif reading == "mirror":
        R = np.stack([-L[:, 0], -L[:, 1], L[:, 2]], axis=1)
        c = np.maximum(np.einsum("ij,ij->i", R, V), 0.0)
    else:
        raise ValueError("reading is 'half' or 'mirror'")
    with np.errstate(divide="ignore"):
        # c^n through logs: exact where it matters and 0 (not NaN) where c = 0
        power = np.where(c > 0.0, np.exp(n * np.log(np.where(c > 0.0, c, 1.0))), 0.0)
    lobe = (n + 2.0) / (2.0 * np.pi) * power
    return kd_term(kd) + lobe[:, None] * albedo[None, :]


def kd_term(kd):
    return np.asarray(kd, dtype=float)[None, :] / np.pi
