"""Bagher et al. 2012 (bbm's `Bagher` model, fits/bagher_sgd.fit) to brdfit's `sgd` family.

bbm evaluates  kd/pi + albedo * K * F * P22 / (pi cos^4 theta_h) * G1(L) G1(V) / (pi NL NV),
brdfit's sgd   rho_d/pi + rho_s * F * exp(-a) / (pi a^p NH^4) * G1(L) G1(V) / (pi NL NV),
so every parameter maps one to one except the two scales albedo and K, which multiply
the same lobe and are one parameter in brdfit: rho_s = albedo * K (per channel), and the
shadowing's scale: bbm's w = c (theta - theta0)^k is brdfit's ((theta - theta0) / s)^k,
so s = c^(-1/k) per channel (the angle past theta0 where w = 1).
"""
import math


def _rgb(v):
    """A colour as three floats (a scalar stands for all three channels)."""
    if isinstance(v, (list, tuple)):
        return [float(x) for x in v]
    return [float(v)] * 3


def to_brdfit(kd, p):
    """The brdfit parameter file (a dict) for one published Bagher fit: kd is the
    Lambertian albedo [r, g, b], p the model's parameters as written in the .fit file."""
    albedo, K = _rgb(p["albedo"]), _rgb(p["K"])
    eta = p["eta"]  # [[f0 r, g, b], [f1 r, g, b]]
    params = {
        "rho_d": _rgb(kd),
        "rho_s": [a * k for a, k in zip(albedo, K)],
        "alpha": _rgb(p["alpha"]),
        "p": _rgb(p["p"]),
        "f0": _rgb(eta[0]),
        "f1": _rgb(eta[1]),
        "lambda": _rgb(p["Lambda"]),
        "s": [math.exp(-math.log(c) / k) for c, k in zip(_rgb(p["c"]), _rgb(p["k"]))],
        "k": _rgb(p["k"]),
        "theta0": _rgb(p["theta0"]),
    }
    return {"model": "sgd", "channels": 3, "params": params}
