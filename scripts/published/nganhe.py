"""bbm's NganHe fits (Ngan et al. 2005) as brdfit parameter files for the family `he`.

bbm writes `NganHe(albedo = [r, g, b], autocorrelation = tau, roughness = sigma, eta = n)`
beside a `Lambertian(albedo = kd)`; the family `he` has the same parameters under brdfit's
names (docs/models.md, "he"), so the mapping is one to one:

    rho_d = kd, rho_s = albedo, tau = autocorrelation, sigma = roughness, eta = eta

tau and sigma stay in micrometres (bbm's wavelengths 0.645, 0.526, 0.444 um are brdfit's).
The one exception: rho_s is bounded by 1e5, and four published fits with eta = 1.0 have
albedo up to 2e9. Their Fresnel factor is exactly 0 at eta = 1 (Ngan's eta was slightly
above 1 and rounded to three digits), so the lobe vanishes whatever the weight: rho_s is
then clamped to the bound, which changes no value.
"""

RHO_S_MAX = 1e5


def to_brdfit(kd, p):
    """Parameter-file dict for brdfit's `he` family from bbm's Lambertian kd and NganHe p."""
    albedo = [float(a) for a in p["albedo"]]
    eta = float(p["eta"])
    if eta == 1.0:
        albedo = [min(a, RHO_S_MAX) for a in albedo]
    elif max(albedo) > RHO_S_MAX:
        raise ValueError("NganHe albedo %g is above he's rho_s bound %g" % (max(albedo), RHO_S_MAX))
    return {
        "model": "he",
        "channels": 3,
        "params": {
            "rho_d": [float(v) for v in kd],
            "rho_s": albedo,
            "tau": float(p["autocorrelation"]),
            "sigma": float(p["roughness"]),
            "eta": eta,
        },
    }
