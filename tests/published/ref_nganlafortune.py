"""Independent reference: Ngan et al. 2005's one-lobe isotropic Lafortune as
bsdfbenchmark/bbm defines it (Lafortune's lobe times Ngan's (n+2)/(2 pi max(|Cz|,|Cxy|)^n)),
plus the Lambertian:
    f = kd/pi + albedo (n+2)/(2 pi) max(d, 0)^n / cmax^n,
    d = Cxy (Lx Vx + Ly Vy) + Cz Lz Vz,  cmax = max(|Cxy|, |Cz|).
max(d/cmax, 0)^n rather than d^n / cmax^n, which underflow to 0/0 for large n."""
import numpy as np


def evaluate(kd, p, L, V):
    L = np.asarray(L, dtype=float)
    V = np.asarray(V, dtype=float)
    cxy, cz, n = float(p["Cxy"]), float(p["Cz"]), float(p["sharpness"])
    cmax = max(abs(cxy), abs(cz))
    d = cxy * (L[:, 0] * V[:, 0] + L[:, 1] * V[:, 1]) + cz * L[:, 2] * V[:, 2]
    r = np.clip(d / cmax, 0.0, None)
    lobe = (n + 2.0) / (2.0 * np.pi) * r**n
    rho = np.asarray(p["albedo"], dtype=float)
    if rho.ndim == 0:
        rho = np.full(3, float(rho))
    return np.asarray(kd, dtype=float)[None, :] / np.pi + np.outer(lobe, rho)
