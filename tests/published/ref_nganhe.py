"""An independent evaluation of bbm's NganHe fits (He, Torrance, Sillion & Greenberg 1991 in
Westin's formulation, as bbm's include/bsdfmodel/ngan.h configures he.h), written from the
paper's equations, not from brdfit's C code.

    f = kd/pi + albedo F S(L) S(V) G D / (pi NL NV)

G is He's Eq. 76 written with the s and p polarisation vectors; sigma0 solves Eq. 80 by
bisection (not Newton); the series of Eq. 78 is summed in log space over 4000 terms (no
truncation rule); the rough limit (Beckmann 1963) replaces it where g of the longest
wavelength exceeds 19, blended linearly from 18, as bbm does. Per-channel wavelengths
0.645, 0.526, 0.444 micrometres (bbm's RGB configuration).

Where this and bbm differ on purpose (bbm's numerics, not the model): bbm stops the
series on the smallest channel's term (its blue channel is then up to 0.4% low) and takes
4 Newton steps (up to 6e-7 relative at grazing); at exactly L = V or normal incidence
bbm's Eq. 76 is 0/0, where this uses the limit (the bracket ratio is 1 everywhere).
"""
import math

import numpy as np

LAMBDA = np.array([0.645, 0.526, 0.444])
M_TERMS = 4000
_LGAMMA = np.array([math.lgamma(m + 1.0) for m in range(1, M_TERMS + 1)])
_M = np.arange(1, M_TERMS + 1, dtype=float)
_erfc = np.vectorize(math.erfc)


def _tan(w):
    return np.hypot(w[:, 0], w[:, 1]) / w[:, 2]


def _shadow(w, tau, sigma):
    """Eqs. 24-25 with the erratum's exponential: the fraction of the surface seen along w."""
    t = _tan(w)
    out = np.ones(len(w))
    k = t > 0
    s = tau / (2.0 * sigma * t[k])
    half_erfc = 0.5 * _erfc(s)
    lam = np.exp(-s * s) / (2.0 * math.sqrt(math.pi) * s) - half_erfc
    out[k] = (1.0 - half_erfc) / (lam + 1.0)
    return out


def _sigma0(L, V, tau, sigma):
    """Eqs. 80-83 in the form bbm and Westin solve: sigma0 = sigma / sqrt(1 + x^2) with
    x exp(x^2/2) = (K_i + K_r)/sqrt(8 pi), K = tan erfc(tau / (2 sigma tan)); bisection on x."""
    def K(w):
        t = _tan(w)
        out = np.zeros(len(w))
        k = t > 0
        out[k] = t[k] * _erfc(tau / (2.0 * sigma * t[k]))
        return out

    f0 = (K(L) + K(V)) / math.sqrt(8.0 * math.pi)
    lo = np.zeros_like(f0)
    hi = np.maximum(1.0, np.sqrt(2.0 * np.log(np.maximum(f0, 1.0)))) + 1.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        above = mid * np.exp(0.5 * mid * mid) > f0
        hi = np.where(above, mid, hi)
        lo = np.where(above, lo, mid)
    x = 0.5 * (lo + hi)
    return sigma / np.sqrt(1.0 + x * x)


def _geometry_factor(L, V):
    """Eq. 76: (v.v / v_z)^2 |s_r.k_i ...|^2 .. / |k_i x k_r|^4 with k_i = -L, k_r = V."""
    ki, kr = -L, V
    n = np.array([0.0, 0.0, 1.0])
    v = kr - ki
    out = (np.einsum("ij,ij->i", v, v) / v[:, 2]) ** 2
    cross = np.cross(ki, kr)
    c2 = np.einsum("ij,ij->i", cross, cross)
    ok = (c2 > 1e-24) & (np.hypot(L[:, 0], L[:, 1]) > 1e-12) & (np.hypot(V[:, 0], V[:, 1]) > 1e-12)

    def sp(k):
        s = np.cross(k, n)
        s /= np.linalg.norm(s, axis=1)[:, None]
        return s, np.cross(s, k)

    si, pi_ = sp(ki[ok])
    sr, pr = sp(kr[ok])
    a = np.einsum("ij,ij->i", sr, ki[ok]) ** 2 + np.einsum("ij,ij->i", pr, ki[ok]) ** 2
    b = np.einsum("ij,ij->i", si, kr[ok]) ** 2 + np.einsum("ij,ij->i", pi_, kr[ok]) ** 2
    out[ok] *= a * b / c2[ok] ** 2
    return out


def _fresnel(c, eta):
    """Cook & Torrance 1982, real index eta, c = V.H."""
    g = np.sqrt(np.maximum(eta * eta + c * c - 1.0, 0.0))
    a = (g - c) / (g + c)
    b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0)
    return 0.5 * a * a * (1.0 + b * b)


def _distribution(L, V, tau, s0):
    """Eqs. 78-79 (Westin's exponent pi^2 tau^2 v_xy^2 / lambda^2), per channel."""
    vxy2 = (L[:, 0] + V[:, 0]) ** 2 + (L[:, 1] + V[:, 1]) ** 2
    cz = L[:, 2] + V[:, 2]
    g = (2.0 * math.pi * s0[:, None] * cz[:, None] / LAMBDA[None, :]) ** 2
    b = math.pi ** 2 * tau ** 2 * vxy2[:, None] / LAMBDA[None, :] ** 2
    norm = math.pi ** 2 * tau ** 2 / (4.0 * LAMBDA ** 2)
    logt = (-g[:, :, None] + _M * np.log(g)[:, :, None] - _LGAMMA - np.log(_M) - b[:, :, None] / _M)
    series = np.exp(logt).sum(axis=2)
    rough = np.exp(-b / g) / g
    w = np.clip(g[:, 0] - 18.0, 0.0, 1.0)[:, None]  # the longest wavelength's g
    return norm[None, :] * ((1.0 - w) * series + w * rough)


def evaluate(kd, p, L, V):
    """RGB BRDF values (N, 3), the Lambertian kd/pi included, for unit L, V of shape (N, 3)."""
    L = np.asarray(L, dtype=float)
    V = np.asarray(V, dtype=float)
    tau, sigma, eta = float(p["autocorrelation"]), float(p["roughness"]), float(p["eta"])
    albedo = np.asarray(p["albedo"], dtype=float)
    s0 = _sigma0(L, V, tau, sigma)
    H = L + V
    c = np.linalg.norm(H, axis=1) / 2.0  # V.H
    lobe = (_fresnel(c, eta) * _shadow(L, tau, sigma) * _shadow(V, tau, sigma) * _geometry_factor(L, V)
            / (math.pi * L[:, 2] * V[:, 2]))
    return np.asarray(kd, dtype=float)[None, :] / math.pi + albedo[None, :] * lobe[:, None] * _distribution(L, V, tau, s0)
