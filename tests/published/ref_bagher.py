"""Independent reference for Bagher, Soler & Holzschuch 2012 ("Accurate fitting of measured
reflectances using a Shifted Gamma micro-facet distribution", CGF 31(4)) as bbm defines
its `Bagher` model: a scaled Cook-normalised microfacet BRDF with the Shifted Gamma
Distribution, Bagher's Fresnel approximation and uncorrelated fitted shadowing, plus
the Lambertian kd/pi of the published aggregate. Parameters as in the .fit file."""
import numpy as np


def _col(v):
    return np.broadcast_to(np.asarray(v, dtype=float), (3,))


def evaluate(kd, p, L, V):
    """(N, 3) RGB BRDF values at unit directions L, V (N, 3), z = normal."""
    L = np.asarray(L, dtype=float)
    V = np.asarray(V, dtype=float)
    albedo, alpha, pp = _col(p["albedo"]), _col(p["alpha"]), _col(p["p"])
    K, lam, c, k, th0 = _col(p["K"]), _col(p["Lambda"]), _col(p["c"]), _col(p["k"]), _col(p["theta0"])
    f0, f1 = _col(p["eta"][0]), _col(p["eta"][1])

    H = L + V
    H = H / np.linalg.norm(H, axis=1, keepdims=True)
    cos_h = H[:, 2:3]
    tan2 = (H[:, 0:1] ** 2 + H[:, 1:2] ** 2) / cos_h**2
    # Shifted Gamma Distribution: P22 = exp(-(alpha + tan^2/alpha)) / (alpha + tan^2/alpha)^p
    s = alpha + tan2 / alpha
    P22 = np.exp(-s) / s**pp
    D = K * P22 / (np.pi * cos_h**4)

    # Bagher's Fresnel: Schlick's with f0, less f1 cos(theta_d); theta_d from L.H = V.H
    cd = (0.5 * (np.sum(L * H, axis=1) + np.sum(V * H, axis=1)))[:, None]
    F = f0 + (1.0 - f0) * (1.0 - cd) ** 5 - f1 * cd

    def G1(W):
        theta = np.arccos(np.clip(W[:, 2:3], -1.0, 1.0))
        d = theta - th0
        over = d > 0
        dd = np.where(over, d, 1.0)
        # 1 - e^w as -expm1(w): w reaches 1e-12 where Lambda is 1e7 (ss440), and 1 - exp(w)
        # would lose all but 4 digits of the product.
        with np.errstate(over="ignore"):  # the branch np.where discards (theta <= theta0)
            g = 1.0 - lam * np.expm1(c * dd**k)
        return np.where(over, g, 1.0)

    G = G1(L) * G1(V)
    nl, nv = L[:, 2:3], V[:, 2:3]
    spec = albedo * D * G * F / np.pi / (nl * nv)
    return _col(kd) / np.pi + spec
