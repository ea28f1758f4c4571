"""Löw et al. 2012's microfacet (ABC) fits (bsdfbenchmark/bbm `LowMicrofacetFit`) as
brdfit's `abc:fresnel=dielectric`.

bbm's LowMicrofacetFit is its microfacet model with Low's unnormalised distribution
(1 + B (1 - NH))^-C, V-groove shadowing, Cook-Torrance's dielectric Fresnel of eta at
L.H, and the normalisation factor pi of the fits in Low et al.'s supplemental material:
A D G F / (pi NL NV). brdfit's abc writes rho_s D G_ct F / (pi NL NV), so the mapping is
the identity: rho_s = A, b = B, c = C, ior = eta, rho_d = kd. Every published fit is
inside the bounds (A <= 5.8e3 of 1e5, B <= 8.1e6 of 1e7, C <= 2.7 of 10, eta <= 99.9996
of 100: four fits end at Low et al.'s own bound of 100).
"""


def to_brdfit(kd, p):
    """The brdfit parameter-file dict of one published LowMicrofacetFit fit."""
    return {
        "model": "abc:fresnel=dielectric",
        "channels": 3,
        "params": {
            "rho_d": [float(v) for v in kd],
            "rho_s": [float(v) for v in p["A"]],
            "b": float(p["B"]),
            "c": float(p["C"]),
            "ior": float(p["eta"]),
        },
    }
