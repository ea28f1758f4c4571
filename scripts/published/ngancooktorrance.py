"""Ngan, Durand & Matusik 2005 (EGSR) Cook-Torrance, as published in bsdfbenchmark/bbm
fits/ngan_cooktorrance.fit, to brdfit's cook_torrance (fresnel=schlick).

bbm evaluates albedo D G F / (pi NL NV) with D the Beckmann distribution normalised by
1/pi (exp(-tan^2/m^2) / (pi m^2 NH^4)), G the V-groove, F Schlick with F0 = the
parameter bbm names eta. brdfit's cook_torrance is rho_s D G F / (4 NL NV) with the same
D, G and F, so
    rho_d = kd,  rho_s = 4 albedo / pi,  m = roughness,  f0 = eta.
One published fit (colonial-maple-223, red albedo 0.981: rho_s 1.249) lies above
brdfit's bound rho_s <= 1, which keeps the albedo <= 1 where Schlick's F tends to 1 at
grazing incidence; brdfit eval refuses it (docs/models.md)."""

import math


def _rgb(v):
    return [float(x) for x in v] if isinstance(v, (list, tuple)) else [float(v)] * 3


def to_brdfit(kd, p):
    return {
        "model": "cook_torrance",
        "channels": 3,
        "params": {
            "rho_d": _rgb(kd),
            "rho_s": [4.0 * a / math.pi for a in _rgb(p["albedo"])],
            "m": float(p["roughness"]),
            "f0": float(p["eta"]),
        },
    }
