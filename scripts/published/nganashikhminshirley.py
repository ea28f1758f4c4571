"""Ngan, Durand & Matusik 2005 (EGSR) Ashikhmin-Shirley (isotropic lobe beside a plain
Lambertian), as published in bsdfbenchmark/bbm fits/ngan_ashikhminshirley.fit, to
brdfit's ashikhmin_shirley_iso:diffuse=lambert (the same formula):
    f = kd/pi + albedo (n+1)/(8 pi) NH^n F(VH) / (VH max(NL, NV)),
    F = f0 + (1 - f0)(1 - VH)^5.
rho_d = kd, rho_s = albedo, n = sharpness, f0 = fresnelReflectance (no conversion)."""


def _rgb(v):
    return [float(x) for x in v] if isinstance(v, (list, tuple)) else [float(v)] * 3


def to_brdfit(kd, p):
    return {
        "model": "ashikhmin_shirley_iso:diffuse=lambert",
        "channels": 3,
        "params": {
            "rho_d": _rgb(kd),
            "rho_s": _rgb(p["albedo"]),
            "n": float(p["sharpness"]),
            "f0": float(p["fresnelReflectance"]),
        },
    }
