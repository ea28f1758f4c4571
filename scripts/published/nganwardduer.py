"""Ngan, Durand & Matusik 2005 (EGSR), Ward with Duer's normalisation (bbm's WardDuer,
isotropic), as published in bsdfbenchmark/bbm fits/ngan_wardduer.fit, to brdfit's
ward_iso:norm=duer (the same formula):
    f = kd/pi + albedo exp(-tan^2(theta_h)/a^2) / (4 pi a^2 NL NV).
rho_d = kd, rho_s = albedo, alpha = roughness (no conversion)."""


def _rgb(v):
    return [float(x) for x in v] if isinstance(v, (list, tuple)) else [float(v)] * 3


def to_brdfit(kd, p):
    return {
        "model": "ward_iso:norm=duer",
        "channels": 3,
        "params": {"rho_d": _rgb(kd), "rho_s": _rgb(p["albedo"]), "alpha": float(p["roughness"])},
    }
