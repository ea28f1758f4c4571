"""Ngan, Durand & Matusik 2005 (EGSR) "Blinn-Phong", as published in bsdfbenchmark/bbm
fits/ngan_blinnphong.fit, to a brdfit parameter file.

Two readings of the published numbers (docs/models.md, "Published fits"):
- "half" (default, brdfit's choice): the lobe of the model's name, around the half
  vector, albedo (n+2)/(2 pi) NH^n. brdfit's blinn_phong has the exact normalisation
  N(n) = (n+2)(n+4) / (8 pi (2^(-n/2) + n)), so
      rho_s = albedo (n+2)/(2 pi) / N(n) = albedo 4 (2^(-n/2) + n) / (n + 4),  n = sharpness.
- "mirror": what bbm evaluates, albedo (n+2)/(2 pi) max(R.V, 0)^n: brdfit's phong with
  rho_s = albedo, n = sharpness.
rho_d = kd in both."""


def _rgb(v):
    return [float(x) for x in v] if isinstance(v, (list, tuple)) else [float(v)] * 3


def to_brdfit(kd, p, reading="half"):
    n = float(p["sharpness"])
    albedo = _rgb(p["albedo"])
    if reading == "mirror":
        return {"model": "phong", "channels": 3, "params": {"rho_d": _rgb(kd), "rho_s": albedo, "n": n}}
    if reading != "half":
        raise ValueError("reading is 'half' or 'mirror'")
    scale = 4.0 * (2.0 ** (-0.5 * n) + n) / (n + 4.0)
    return {
        "model": "blinn_phong",
        "channels": 3,
        "params": {"rho_d": _rgb(kd), "rho_s": [a * scale for a in albedo], "n": n},
    }
