"""Independent reference for brdfit's student_t family (Ribardiere, Bringier, Meneveaux &
Simonot 2017, "STD: Student's t-Distribution of Slopes for Microfacet Based BSDFs"), written
from the docs/models.md formula with numpy alone: the Smith Lambda by quadrature of its
defining integral, not by the incomplete beta function the library evaluates.

    f = rho_d/pi + sum_k rho_s D G1(L) G1(V) F / (4 NL NV)
    D = 1 / (pi alpha^2 NH^4 (1 + tan^2(theta_h) / ((gamma - 1) alpha^2))^gamma)
    G1(w) = 1 / (1 + Lambda(z)), z = 1 / (alpha tan(theta_w))
    Lambda(z) = (1/z) int_z^inf (q - z) P2(q) dq,
    P2(q) = Gamma(gamma - 1/2) / (sqrt(pi (gamma - 1)) Gamma(gamma - 1)) (1 + q^2/(gamma - 1))^(1/2 - gamma)

evaluate(params, L, V): params is a brdfit parameter file's dict ({"model": "student_t...",
"options": {...}, "params": {...}}) or its "params" dict alone; L, V are (N, 3) unit
vectors (z = normal, upper hemisphere). Returns (N, C) values, the Lambertian included.
"""
import math

import numpy as np


def _spec_options(params):
    opts = {"fresnel": "schlick", "lobes": 1}
    model = params.get("model", "student_t") if isinstance(params.get("model"), str) else "student_t"
    if ":" in model:
        for kv in model.split(":", 1)[1].split(","):
            k, v = kv.split("=")
            opts[k] = v
    opts.update(params.get("options", {}))
    return opts["fresnel"], int(opts["lobes"])


def _lambda(z, gamma):
    """Smith Lambda at z (1-d array, z > 0): the q P2 part in closed form, the tail of P2 by
    the trapezoidal rule in s with q = z + e^s (smooth, decaying at both ends)."""
    g1 = gamma - 1.0
    k = math.exp(math.lgamma(gamma - 0.5) - math.lgamma(gamma - 1.0)) / math.sqrt(math.pi * g1)
    first = k * g1 / (2.0 * gamma - 3.0) * (1.0 + z * z / g1) ** (1.5 - gamma) / z
    h = 0.005
    s = np.arange(-45.0, 80.0, h)
    e = np.exp(s)
    q = z[:, None] + e[None, :]
    tail = np.sum(e[None, :] * k * (1.0 + q * q / g1) ** (0.5 - gamma), axis=1) * h
    return first - tail


def _g1(W, alpha, gamma):
    sin = np.hypot(W[:, 0], W[:, 1])
    out = np.ones(len(W))
    m = sin > 0.0
    z = W[m, 2] / (alpha * sin[m])
    out[m] = 1.0 / (1.0 + _lambda(z, gamma))
    return out


def _fresnel(kind, c, p):
    if kind == "schlick":
        return p + (1.0 - p) * (1.0 - c) ** 5
    if kind == "dielectric":  # Cook & Torrance 1982, unpolarised
        g = np.sqrt(p * p - 1.0 + c * c)
        a = (g - c) / (g + c)
        b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0)
        return 0.5 * a * a * (1.0 + b * b)
    return np.ones_like(c)


def evaluate(params, L, V):
    L = np.asarray(L, dtype=float)
    V = np.asarray(V, dtype=float)
    fresnel, lobes = _spec_options(params)
    p = params.get("params", params)
    rho_d = np.atleast_1d(np.asarray(p["rho_d"], dtype=float))
    C = len(rho_d)
    H = L + V
    H /= np.linalg.norm(H, axis=1)[:, None]
    nh = H[:, 2]
    vh = np.sum(V * H, axis=1)
    tan2 = (H[:, 0] ** 2 + H[:, 1] ** 2) / (nh * nh)
    out = np.tile(rho_d / math.pi, (len(L), 1))
    for k in range(1, lobes + 1):
        sfx = "" if lobes == 1 else "_%d" % k
        rho_s = np.broadcast_to(np.atleast_1d(np.asarray(p["rho_s" + sfx], dtype=float)), (C,))
        alpha, gamma = float(p["alpha" + sfx]), float(p["gamma" + sfx])
        D = 1.0 / (math.pi * alpha**2 * nh**4 * (1.0 + tan2 / ((gamma - 1.0) * alpha**2)) ** gamma)
        G = _g1(L, alpha, gamma) * _g1(V, alpha, gamma)
        fp = float(p["f0" + sfx]) if fresnel == "schlick" else float(p["ior" + sfx]) if fresnel == "dielectric" else 0.0
        F = _fresnel(fresnel, vh, fp)
        lobe = D * G * F / (4.0 * L[:, 2] * V[:, 2])
        out += lobe[:, None] * rho_s[None, :]
    return out
