"""Löw et al. 2012's Ashikhmin-Shirley fits (bsdfbenchmark/bbm `LowAshikhminShirley`) as
brdfit's `ashikhmin_shirley_iso:diffuse=lambert,fresnel=dielectric`.

bbm evaluates kd/pi + albedo (n + 1)/(8 pi) NH^n F_d(L.H; eta) / (L.H max(NL, NV)), with
`fresnelReflectance` the index of refraction eta of Cook-Torrance's dielectric Fresnel
(not a reflectance: its values run from 1.08 to 10.1). That is brdfit's
ashikhmin_shirley_iso with a plain Lambertian (diffuse=lambert, Ngan 2005's variant) and
the dielectric Fresnel (fresnel=dielectric): rho_d = kd, rho_s = albedo, n = sharpness,
ior = fresnelReflectance. Both options must be in the brdfit that reads the file
(diffuse= comes with the Ngan 2005 work, fresnel= on top of it).

Outside the bounds, not clipped (brdfit rejects them): rho_s <= 1 (energy conservation)
excludes albedo up to 1.82 in six fits (E1: light-brown-fabric, polyethylene,
red-fabric2, white-paint; E2: polyethylene, red-fabric2). Sharpness goes down to 0.002,
inside diffuse=lambert's [0, 1e6].
"""


def to_brdfit(kd, p):
    """The brdfit parameter-file dict of one published LowAshikhminShirley fit."""
    return {
        "model": "ashikhmin_shirley_iso:diffuse=lambert,fresnel=dielectric",
        "channels": 3,
        "params": {
            "rho_d": [float(v) for v in kd],
            "rho_s": [float(v) for v in p["albedo"]],
            "n": float(p["sharpness"]),
            "ior": float(p["fresnelReflectance"]),
        },
    }
