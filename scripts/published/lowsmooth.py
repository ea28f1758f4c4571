"""Löw et al. 2012's smooth-surface fits (bsdfbenchmark/bbm `LowSmooth`) as brdfit's
`low_smooth:fresnel=dielectric`.

bbm evaluates A (1 + B |L_xy + V_xy|^2)^-C F(eta, sqrt(1 - |L_xy - V_xy|^2 / 4)) beside a
Lambertian kd/pi, which is brdfit's formula term for term: rho_s = A, b = B, c = C,
ior = eta, rho_d = kd. Every published fit is inside the bounds (A <= 2.4e3 of 1e5,
B <= 4.6e6 of 1e7, C <= 2.3 of 10, eta <= 9.1 of 100).
"""


def to_brdfit(kd, p):
    """The brdfit parameter-file dict of one published LowSmooth fit."""
    return {
        "model": "low_smooth:fresnel=dielectric",
        "channels": 3,
        "params": {
            "rho_d": [float(v) for v in kd],
            "rho_s": [float(v) for v in p["A"]],
            "b": float(p["B"]),
            "c": float(p["C"]),
            "ior": float(p["eta"]),
        },
    }
