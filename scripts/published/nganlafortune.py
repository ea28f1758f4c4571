"""Ngan, Durand & Matusik 2005 (EGSR) single isotropic Lafortune lobe, as published in
bsdfbenchmark/bbm fits/ngan_lafortune.fit, to brdfit's lafortune (normalised as Ngan):
    f = kd/pi + albedo (n+2)/(2 pi) max(d, 0)^n / cmax^n,
    d = Cxy (Lx Vx + Ly Vy) + Cz Lz Vz,  cmax = max(|Cxy|, |Cz|).
rho_d = kd, rho_s = albedo, cxy = Cxy, cz = Cz, n = sharpness (no conversion).
Two published fits have an albedo above brdfit's rho_s <= 1 (black-phenolic red 1.71,
pvc red 1.07); brdfit eval refuses them (docs/models.md)."""


def _rgb(v):
    return [float(x) for x in v] if isinstance(v, (list, tuple)) else [float(v)] * 3


def to_brdfit(kd, p):
    return {
        "model": "lafortune",
        "channels": 3,
        "params": {
            "rho_d": _rgb(kd),
            "rho_s": _rgb(p["albedo"]),
            "cxy": float(p["Cxy"]),
            "cz": float(p["Cz"]),
            "n": float(p["sharpness"]),
        },
    }
