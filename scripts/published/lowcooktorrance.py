"""Löw et al. 2012's Cook-Torrance fits (bsdfbenchmark/bbm `LowCookTorrance`) as brdfit's
`cook_torrance:fresnel=dielectric`.

bbm evaluates albedo D G F / (pi NL NV) with D = exp(-tan^2(theta_h)/m^2) / (m^2 NH^4),
the Beckmann distribution WITHOUT its 1/pi, V-groove G and Cook-Torrance's dielectric
Fresnel of eta at L.H. brdfit's cook_torrance is rho_s D_b G F / (4 NL NV) with
D_b = D / pi, so rho_s = 4 albedo; m = roughness, ior = eta, rho_d = kd.

Not every fit is inside brdfit's bounds, and the mapping does not clip (brdfit rejects
them): rho_s <= 1 (energy conservation) excludes albedo > 0.25, and m <= 1 (the
microfacet family's Beckmann bound) excludes roughness > 1. E1: white-paint (rho_s up
to 1.148), white-fabric2 (rho_s up to 1.364, m = 2.094), polyurethane-foam
(m = 1.138); E2: polyurethane-foam (m = 1.126). The other 196 of 200 fits map exactly.
"""


def to_brdfit(kd, p):
    """The brdfit parameter-file dict of one published LowCookTorrance fit."""
    return {
        "model": "cook_torrance:fresnel=dielectric",
        "channels": 3,
        "params": {
            "rho_d": [float(v) for v in kd],
            "rho_s": [4.0 * float(v) for v in p["albedo"]],
            "m": float(p["roughness"]),
            "ior": float(p["eta"]),
        },
    }
