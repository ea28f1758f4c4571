"""Ngan, Durand & Matusik 2005 (EGSR), isotropic Ward, as published in bsdfbenchmark/bbm
fits/ngan_ward.fit, to brdfit's ward_iso (the same formula):
    f = kd/pi + albedo exp(-tan^2(theta_h)/a^2) / (4 pi a^2 sqrt(NL NV)).
rho_d = kd, rho_s = albedo, alpha = roughness (no conversion)."""


def _rgb(v):
    return [float(x) for x in v] if isinstance(v, (list, tuple)) else [float(v)] * 3


def to_brdfit(kd, p):
    return {
        "model": "ward_iso",
        "channels": 3,
        "params": {"rho_d": _rgb(kd), "rho_s": _rgb(p["albedo"]), "alpha": float(p["roughness"])},
    }
