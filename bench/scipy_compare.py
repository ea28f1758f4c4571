#!/usr/bin/python3
"""brdfit against scipy.optimize.least_squares on one fit.

What it measures
    The wall time of `brdfit fit DATA -m walter` (the whole process: read, preprocess,
    start, solve, metrics, standard errors, JSON) against the same fit done in Python
    with numpy and scipy.optimize.least_squares (read, geometry, start, solve), in the
    same run, and the ratio of the two. It also checks that both reach the same log RMSE.

    /usr/bin/python3 bench/scipy_compare.py BRDFIT DATA.binary [--threads N] [--repeats R]
    /usr/bin/python3 bench/scipy_compare.py BRDFIT --self-check

    BRDFIT is run as `BRDFIT fit DATA -m walter --threads N -o TMP.json` R times
    (default 3), the scipy fit R times (default 1: it is slow); the minimum wall time
    of each is reported. Both fits run in this one invocation, one after the other.

    Prints: the data and settings, the start (with the check below), a table of wall
    time, solve time, iterations, final cost (0.5 sum r^2) and log RMSE (sqrt(mean r^2)
    over samples x channels) per tool, both evaluated by this script's residual at each
    tool's final parameters, the parameters, then `ratio scipy/brdfit wall: X.Xx`, the
    solve-time ratio and the relative difference of the two log RMSEs (warning > 1%).
    Bad input (missing file, not a MERL table, brdfit failing): one line, exit 1.

The fit, identical on both sides (lib/src/core/models/microfacet.c, fit/objective.c,
fit/parametrisation.c, io/merl.c, samples_prep.c, geometry.c, merl_cells.c):
  - Data: every MERL cell whose three raw values are >= 0, at its centre direction,
    value = raw * (1, 1.15, 1.66) / 1500. Directions go the way brdfit takes them: cell
    centre -> (theta_i, phi_i, theta_o, phi_o) in degrees -> unit vectors; a sample with
    theta >= 90 degrees or cos theta < 1e-15 on either side is dropped (brdfit's
    preprocessing), so every kept sample has cos_i > 0 and cos_o > 0.
  - Model walter (fresnel=schlick, lobes=1), 3 channels, 8 parameters
        x = (rho_d[r, g, b], rho_s[r, g, b], alpha, f0)
        f = rho_d/pi + rho_s D G F / (4 cos_i cos_o)
        D = alpha^2 / (pi (sin^2 theta_h + alpha^2 cos^2 theta_h)^2)   GGX
        G = G1(L) G1(V), G1 = 2 / (1 + sqrt(1 + alpha^2 tan^2 theta))   Smith-GGX
        F = f0 + (1 - f0) (1 - V.H)^5                              Schlick
    bounds rho_d, rho_s, f0 in [0, 1], alpha in [1e-4, 1].
  - Residual (log form, unweighted): r = ln(1 + f cos_i) - ln(1 + m cos_i) per sample
    and channel, each argument floored at -1 + 1e-12; cost = 0.5 sum r^2.
  - Internal parametrisation: alpha is optimised as z = ln(alpha) (bounds
    [ln 1e-4, 0]), the others as themselves; the Jacobian is analytic (jac=callable),
    with the chain rule d alpha / dz = alpha, as brdfit's.
  - Start: brdfit's data-driven start (lib/src/fit/init.c), ported below for this model
    (data_driven_start), because the CLI neither takes a start (no --start or --init)
    nor reports its own (--max-iterations must be positive; the JSON has only the final
    parameters). So no fixed start was needed. The port is checked on every run: the
    cost at the ported start is printed next to the optimizer.initial_cost of an untimed
    `brdfit fit --presolve off --max-iterations 1` (the timed run presolves, so its
    initial cost is where its solve on all samples began), with a warning when they
    differ by more than 1e-9 (init.c changed).
  - Solver: brdfit runs its defaults: Ceres Levenberg-Marquardt (100 iterations at most,
    function tolerance 1e-10, parameter tolerance 1e-10, gradient tolerance 1e-12) on a
    seeded stratified subsample of 32768 samples (the presolve), then from there on all
    samples (function tolerance 1e-9); scipy runs least_squares(method='trf', bounds,
    one start) on all samples with the first three tolerances (ftol, xtol, gtol: the same
    tests, up to scipy's scaling). The presolve is brdfit's algorithm, not a shortcut:
    both reach the same optimum (the log RMSEs are compared below).
  - Threads: brdfit gets --threads N (default: every core). numpy's element-wise work is
    single-threaded; the BLAS/LAPACK thread variables are set to N before numpy loads
    (whether they matter depends on the BLAS Debian's alternatives point at).
  - Times: brdfit's wall time is the whole process (read, preprocessing, start, solve,
    metrics, standard errors, JSON) and its solve time Ceres' own, presolve included
    (optimizer.seconds + optimizer.presolve.seconds);
    scipy's wall time is read + geometry + start + least_squares in this process, and
    its solve time least_squares alone.
  - Speed-ups allowed on the scipy side: every parameter-independent term (tan^2 of both
    directions, (1 - V.H)^5, 1/(4 cos_i cos_o), ln(1 + m cos_i)) is computed once, and
    the model's terms are shared between the residual and Jacobian calls at the same
    point. brdfit also precomputes ln(1 + m cos_i).

--self-check evaluates walter at 400 random directions (half near the mirror direction)
for 5 parameter sets with this script and with `BRDFIT eval`, prints the largest
relative difference and exits 1 above 1e-9 (the directions use the C library's sin and
cos there, so both sides see the same bits); it also checks the analytic Jacobian of the
log residual against central differences (exit 1 above 1e-5).
"""

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time


def _set_blas_threads(argv):
    """BLAS/LAPACK libraries read their thread count when they load, i.e. when numpy is
    imported: set it from --threads (default every core) first, unless the caller has."""
    threads = str(os.cpu_count() or 1)
    for i, a in enumerate(argv):
        if a == "--threads" and i + 1 < len(argv):
            threads = argv[i + 1]
        elif a.startswith("--threads="):
            threads = a.split("=", 1)[1]
    for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(var, threads)


_set_blas_threads(sys.argv[1:])

import numpy as np  # noqa: E402
from scipy.optimize import least_squares  # noqa: E402

# ---- Constants -----------------------------------------------------------------------

MERL_DIMS = (90, 90, 180)  # theta_h, theta_d, phi_d bins
MERL_CELLS = 90 * 90 * 180
MERL_BYTES = 12 + 3 * MERL_CELLS * 8
MERL_SCALE = (1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0)

CHANNELS = 3
NPAR = 8  # rho_d[3], rho_s[3], alpha, f0
I_RHO_D, I_RHO_S, I_ALPHA, I_F0 = 0, 3, 6, 7
X_LO = np.array([0.0] * 6 + [1e-4, 0.0])
X_HI = np.array([1.0] * 6 + [1.0, 1.0])
X_DEFAULT = np.array([0.5] * 6 + [0.12, 0.04])  # microfacet.c: alpha 0.12 k for lobe k

LOG_FLOOR = -1.0 + 1e-12  # objective_state.h: ln(1 + u) with u floored here
HORIZON = 1e-15  # a cosine below this is the horizon (geometry.h)

# Ceres settings brdfit uses by default (optim/ceres_solver.cc), given to scipy too.
FTOL, XTOL, GTOL = 1e-10, 1e-10, 1e-12

SELF_CHECK_LIMIT = 1e-9
RMSE_WARN = 0.01


class InputError(Exception):
    """Bad input: reported as one line, exit status 1."""


# ---- Reading a MERL table (io/merl.c) ----------------------------------------------------


def read_merl(path):
    """Cell indices (increasing) and values (n, 3) of the valid cells of a MERL table."""
    try:
        size = os.path.getsize(path)
    except OSError as e:
        raise InputError(f"{path}: cannot open: {e.strerror}")
    if not os.path.isfile(path):
        raise InputError(f"{path}: not a regular file")
    if size != MERL_BYTES:
        raise InputError(f"{path}: not a MERL table: {size} bytes, a 90 x 90 x 180 table is {MERL_BYTES}")
    with open(path, "rb") as fp:
        dims = np.frombuffer(fp.read(12), dtype="<i4")
        if tuple(int(d) for d in dims) != MERL_DIMS:
            raise InputError(f"{path}: not a MERL table: dimensions {' x '.join(str(int(d)) for d in dims)}, "
                             "expected 90 x 90 x 180")
        raw = np.fromfile(fp, dtype="<f8", count=3 * MERL_CELLS).reshape(3, MERL_CELLS)
    if not np.all(np.isfinite(raw)):
        raise InputError(f"{path}: not a MERL table: NaN or Inf raw values")
    cells = np.flatnonzero((raw >= 0.0).all(axis=0))
    values = np.empty((cells.size, CHANNELS))
    for c in range(CHANNELS):
        values[:, c] = raw[c, cells] * MERL_SCALE[c]
    return cells, values


def merl_cell_angles(cells):
    """Centre directions of MERL cells in degrees, as bf_merl_cell_angles computes them."""
    i = cells // (90 * 180)
    j = cells // 180 % 90
    k = cells % 180
    u = (np.arange(90) + 0.5) / 90
    theta_h = u * u * (math.pi / 2)
    theta_d = (np.arange(90) + 0.5) / 90 * (math.pi / 2)
    phi_d = (np.arange(180) + 0.5) / 180 * math.pi
    sth, cth = np.sin(theta_h)[i], np.cos(theta_h)[i]
    std, ctd = np.sin(theta_d)[j], np.cos(theta_d)[j]
    dx = std * np.cos(phi_d)[k]
    dy = std * np.sin(phi_d)[k]
    dz = ctd
    lx, lz = dx * cth + dz * sth, dz * cth - dx * sth
    vx, vz = dz * sth - dx * cth, dz * cth + dx * sth
    r2d = 180.0 / math.pi
    theta_i = np.arctan2(np.sqrt(lx * lx + dy * dy), lz) * r2d
    phi_i = np.arctan2(dy, lx) * r2d
    theta_o = np.arctan2(np.sqrt(vx * vx + dy * dy), vz) * r2d
    phi_o = (np.arctan2(-dy, vx) + 2 * math.pi) * r2d
    return theta_i, phi_i, theta_o, phi_o


def above_horizon(theta_deg):
    """Not dropped as below the horizon by brdfit's preprocessing (samples_prep.c)."""
    return (theta_deg < 90.0) & (np.cos(theta_deg * (math.pi / 180.0)) >= HORIZON)


# ---- Geometry (geometry.c) -----------------------------------------------------------------


def _horizon(c):
    return np.where(np.abs(c) < HORIZON, 0.0, c)


def _with_half_vector(g):
    """Adds H, V.H = |L + V| / 2 and sin^2 theta_h to a dict holding L and V."""
    x, y, z = g["lx"] + g["vx"], g["ly"] + g["vy"], g["lz"] + g["vz"]
    length = np.sqrt(x * x + y * y + z * z)
    ok = length > 0.0
    safe = np.where(ok, length, 1.0)
    g["hx"] = np.where(ok, x / safe, 0.0)
    g["hy"] = np.where(ok, y / safe, 0.0)
    g["hz"] = np.where(ok, z / safe, 1.0)
    g["vh"] = 0.5 * length
    g["sin2h"] = g["hx"] * g["hx"] + g["hy"] * g["hy"]
    return g


def geometry_from_angles(theta_i, phi_i, theta_o, phi_o, libm_trig=False):
    """Unit vectors (local frame, N = +z) from angles in degrees (bf_samples_geometry).

    numpy's vectorised sin and cos may differ from the C library's by an ulp or two;
    libm_trig=True uses the C library's (slower), so that the directions are bit for bit
    brdfit's. The self-check needs that: Schlick's (1 - V.H)^5 near V.H = 1 turns an ulp
    of V.H into a relative difference of 1e-11 in F. A fit does not."""
    sin, cos = (np.vectorize(math.sin), np.vectorize(math.cos)) if libm_trig else (np.sin, np.cos)
    d2r = math.pi / 180.0
    ti, pi_, to, po = theta_i * d2r, phi_i * d2r, theta_o * d2r, phi_o * d2r
    si, so = sin(ti), sin(to)
    g = {"lx": si * cos(pi_), "ly": si * sin(pi_), "lz": _horizon(cos(ti)),
         "vx": so * cos(po), "vy": so * sin(po), "vz": _horizon(cos(to))}
    return _with_half_vector(g)


def geometry_from_vectors(L, V):
    """Geometry from (n, 3) directions, normalised (bf_geometry_from_vectors)."""
    il = 1.0 / np.sqrt(L[:, 0] * L[:, 0] + L[:, 1] * L[:, 1] + L[:, 2] * L[:, 2])
    iv = 1.0 / np.sqrt(V[:, 0] * V[:, 0] + V[:, 1] * V[:, 1] + V[:, 2] * V[:, 2])
    g = {"lx": L[:, 0] * il, "ly": L[:, 1] * il, "lz": _horizon(L[:, 2] * il),
         "vx": V[:, 0] * iv, "vy": V[:, 1] * iv, "vz": _horizon(V[:, 2] * iv)}
    return _with_half_vector(g)


def valid(g):
    return (g["lz"] > 0.0) & (g["vz"] > 0.0)


def load_samples(path):
    """brdfit's sample set of a MERL file: geometry dict and values (n, 3)."""
    cells, values = read_merl(path)
    angles = merl_cell_angles(cells)
    keep = above_horizon(angles[0]) & above_horizon(angles[2])
    g = geometry_from_angles(*(a[keep] for a in angles))
    return g, values[keep]


# ---- The model: walter, fresnel=schlick, lobes=1 (models/microfacet.c, terms.h) ------------


class WalterTerms:
    """The parameter-independent part of walter on one geometry, and the lobe shape
    S = D G F / (4 cos_i cos_o) with dS/dalpha and dS/df0 at given (alpha, f0)."""

    def __init__(self, g):
        self.valid = valid(g)
        lz = np.where(self.valid, g["lz"], 1.0)  # keeps 1/0 out of invalid samples
        vz = np.where(self.valid, g["vz"], 1.0)
        self.sin2h = g["sin2h"]
        self.hz2 = g["hz"] * g["hz"]
        self.tan2_l = (g["lx"] * g["lx"] + g["ly"] * g["ly"]) / (lz * lz)
        self.tan2_v = (g["vx"] * g["vx"] + g["vy"] * g["vy"]) / (vz * vz)
        m = np.maximum(1.0 - g["vh"], 0.0)
        self.m5 = m * m * m * m * m
        self.inv = np.where(self.valid, 0.25 / (lz * vz), 0.0)

    @staticmethod
    def _g1(tan2, a):
        """Smith-GGX G1 and dG1/dalpha (bf_g1_ggx)."""
        r = np.sqrt(1.0 + a * a * tan2)
        g = 2.0 / (1.0 + r)
        return g, -g / (1.0 + r) * (a * tan2 / r)

    def lobe(self, alpha, f0, grad=True):
        a2 = alpha * alpha
        t = self.sin2h + a2 * self.hz2
        D = a2 / (math.pi * t * t)
        gl, dgl = self._g1(self.tan2_l, alpha)
        gv, dgv = self._g1(self.tan2_v, alpha)
        G = gl * gv
        F = f0 + (1.0 - f0) * self.m5
        S = D * G * F * self.inv
        if not grad:
            return S, None, None
        dD = 2.0 * alpha / (math.pi * t * t) * (1.0 - 2.0 * a2 * self.hz2 / t)
        dS_alpha = (dD * G + D * (dgl * gv + gl * dgv)) * F * self.inv
        dS_f0 = D * G * (1.0 - self.m5) * self.inv
        return S, dS_alpha, dS_f0


def walter_values(terms, x):
    """Model values (n, 3) at parameters x; 0 below the horizon."""
    S, _, _ = terms.lobe(x[I_ALPHA], x[I_F0], grad=False)
    f = x[I_RHO_D:I_RHO_D + 3] * (1.0 / math.pi) + x[I_RHO_S:I_RHO_S + 3] * S[:, None]
    return np.where(terms.valid[:, None], f, 0.0)


def walter_jacobian(terms, x):
    """df/dx (n, 3, 8) in model space (the self-check's reference for the chain rule)."""
    S, dSa, dSf = terms.lobe(x[I_ALPHA], x[I_F0])
    J = np.zeros((S.size, CHANNELS, NPAR))
    for c in range(CHANNELS):
        J[:, c, I_RHO_D + c] = 1.0 / math.pi
        J[:, c, I_RHO_S + c] = S
        J[:, c, I_ALPHA] = x[I_RHO_S + c] * dSa
        J[:, c, I_F0] = x[I_RHO_S + c] * dSf
    return J * terms.valid[:, None, None]


# ---- Internal parametrisation (fit/parametrisation.c) ----------------------------------


def to_internal(x):
    z = np.clip(x, X_LO, X_HI).astype(float)
    z[I_ALPHA] = math.log(z[I_ALPHA])
    return z


def to_model(z):
    x = z.copy()
    x[I_ALPHA] = math.exp(z[I_ALPHA])
    return np.clip(x, X_LO, X_HI)  # exp(ln hi) may round past hi


Z_LO, Z_HI = to_internal(X_LO), to_internal(X_HI)


# ---- The objective (fit/objective.c, objective_state.h) -----------------------------------


class LogObjective:
    """Residuals r = ln(1 + f cos_i) - ln(1 + m cos_i), sample-major (sample i, channel c
    at row 3 i + c), and their Jacobian with respect to the internal vector z."""

    def __init__(self, g, values):
        self.terms = WalterTerms(g)
        self.cos_i = g["lz"][:, None]
        self.meas = np.log1p(np.maximum(values * self.cos_i, LOG_FLOOR))
        self._key = None
        self._cache = None

    def _eval(self, z):
        """Model terms at z, shared by the residual and Jacobian calls at one point."""
        key = z.tobytes()
        if key != self._key:
            x = to_model(z)
            S, dSa, dSf = self.terms.lobe(x[I_ALPHA], x[I_F0])
            f = x[I_RHO_D:I_RHO_D + 3] * (1.0 / math.pi) + x[I_RHO_S:I_RHO_S + 3] * S[:, None]
            u = f * self.cos_i
            self._key, self._cache = key, (x, u, S, dSa, dSf)
        return self._cache

    def residuals(self, z):
        _, u, _, _, _ = self._eval(z)
        return (np.log1p(np.maximum(u, LOG_FLOOR)) - self.meas).ravel()

    def jacobian(self, z):
        """(3 n, 8), Fortran-ordered (the layout LAPACK wants): column k is one contiguous
        (n, 3) block. The colour columns are written whole, zeros included, through an
        identity mask: much faster than strided writes into a zeroed array."""
        x, u, S, dSa, dSf = self._eval(z)
        drdf = np.where(u > LOG_FLOOR, self.cos_i / (1.0 + u), 0.0)  # (n, 3)
        rho_s = x[I_RHO_S:I_RHO_S + 3]
        eye = np.eye(CHANNELS)[:, None, :]
        cols = np.empty((NPAR, S.size, CHANNELS))
        np.multiply(eye, drdf * (1.0 / math.pi), out=cols[I_RHO_D:I_RHO_D + 3])
        np.multiply(eye, drdf * S[:, None], out=cols[I_RHO_S:I_RHO_S + 3])
        np.multiply(drdf, (rho_s * dSa[:, None]) * x[I_ALPHA], out=cols[I_ALPHA])  # d alpha / dz = alpha
        np.multiply(drdf, rho_s * dSf[:, None], out=cols[I_F0])
        return cols.reshape(NPAR, -1).T

    def cost_and_log_rmse(self, x):
        """0.5 sum r^2 and sqrt(mean r^2) over samples x channels at model parameters x."""
        r = self.residuals(to_internal(x))
        ss = float(np.dot(r, r))
        return 0.5 * ss, math.sqrt(ss / r.size)


# ---- brdfit's data-driven start (fit/init.c), for walter ---------------------------------

DIFFUSE_MIN_THETA_H = 25.0 * math.pi / 180.0
NBINS, BIN0, BIN_GROWTH = 36, 1e-3, 1.25
QUANTILE_CAP, SHAPE_CAP, MIN_GROUP = 65536, 8192, 16


def _seq_sum(a):
    """Left-to-right sum, as init.c's loops add (numpy's sum is pairwise)."""
    return float(np.add.accumulate(a)[-1]) if a.size else 0.0


def _bin_of(th):
    b = 1 + np.floor(np.log(np.maximum(th, BIN0) / BIN0) / math.log(BIN_GROWTH)).astype(np.int64)
    return np.where(th < BIN0, 0, np.minimum(b, NBINS - 1))


def _fit_two(y, f1, w):
    """Least squares y ~ d/pi + r f1 with d, r >= 0, weights w (fit_two). -> ssr, d, r."""
    ww = w * w
    s1, sf, sff = _seq_sum(ww), _seq_sum(ww * f1), _seq_sum(ww * f1 * f1)
    sy, syf = _seq_sum(ww * y), _seq_sum(ww * y * f1)
    u = 1.0 / math.pi
    a11, a12, a22, b1, b2 = s1 * u * u, u * sf, sff, u * sy, syf

    def ssr(d, r):
        e = w * (y - d / math.pi - r * f1)
        return _seq_sum(e * e)

    det = a11 * a22 - a12 * a12
    if det > 1e-12 * a11 * a22:
        d, r = (b1 * a22 - b2 * a12) / det, (a11 * b2 - a12 * b1) / det
        if d >= 0.0 and r >= 0.0 and math.isfinite(d) and math.isfinite(r):
            return ssr(d, r), d, r
    r1 = b2 / a22 if a22 > 0.0 and b2 > 0.0 else 0.0
    d2 = b1 / a11 if a11 > 0.0 and b1 > 0.0 else 0.0
    e1, e2 = ssr(0.0, r1), ssr(d2, 0.0)
    if math.isfinite(e1) and (e1 < e2 or not math.isfinite(e2)):
        return e1, 0.0, r1
    return e2, d2, 0.0


def _alpha_of_width(h):
    return min(max(1.4 * min(h, 1.4), X_LO[I_ALPHA]), X_HI[I_ALPHA])


def _fit_at_width(x, h, terms, y, w):
    """Steps 3-4 of init.c at half width h: alpha from h, then per channel rho_d and rho_s
    by least squares against the lobe with unit weight. Updates x; -> ssr, over."""
    x[I_ALPHA] = _alpha_of_width(h)
    f1, _, _ = terms.lobe(x[I_ALPHA], x[I_F0], grad=False)  # rho_d = 0, rho_s = 1
    total, over = 0.0, 0.0
    for c in range(CHANNELS):
        ssr, d, r = _fit_two(y[:, c], f1, w)
        total += ssr
        x[I_RHO_S + c] = min(max(r if r > 0.0 else 1e-3, 0.0), 1.0)
        over = max(over, r)
        x[I_RHO_D + c] = min(max(d, 0.0), 1.0)
    return (total if math.isfinite(total) else math.inf), over


def _scan_widths(x, h, terms, y, w):
    best, best_h = math.inf, h
    for j in range(-6, 11):
        hj = h * 2.0 ** (j / 2.0)
        if hj > 1.4:
            break
        ssr, _ = _fit_at_width(x.copy(), hj, terms, y, w)
        if ssr < best:
            best, best_h = ssr, hj
    return _fit_at_width(x, best_h, terms, y, w)


def data_driven_start(g, values):
    """bf_fit_initial_guess for walter (all samples valid, as after preprocessing)."""
    x = X_DEFAULT.copy()
    th = np.arctan2(np.sqrt(g["sin2h"]), g["hz"])
    # 1. Diffuse level: 15th percentile of f pi far from the peak, per channel.
    far = np.flatnonzero(th > DIFFUSE_MIN_THETA_H)
    if far.size == 0:
        far = np.arange(th.size)
    stride = -(-far.size // QUANTILE_CAP)
    pick = far[::stride][:QUANTILE_CAP]
    diffuse = []
    for c in range(CHANNELS):
        q = np.sort(values[pick, c] * math.pi)
        diffuse.append(float(q[int(0.15 * (q.size - 1) + 0.5)]))
    x[I_RHO_D:I_RHO_D + 3] = diffuse
    # 2. Peak of the excess over the diffuse level in theta_h bins (small bins merged).
    dmean = 0.0
    for d in diffuse:
        dmean += d / (math.pi * CHANNELS)
    v = values[:, 0] / CHANNELS + values[:, 1] / CHANNELS + values[:, 2] / CHANNELS
    bins = _bin_of(th)
    bsum = np.bincount(bins, weights=v - dmean, minlength=NBINS)  # sequential, like C
    bcnt = np.bincount(bins, minlength=NBINS)
    gsum, gcnt, gt = [], [], []
    g0, acc_s, acc_n = 0, 0.0, 0
    for b in range(NBINS):
        acc_s += bsum[b]
        acc_n += int(bcnt[b])
        if acc_n >= MIN_GROUP or (b == NBINS - 1 and acc_n > 0):
            lo_edge = 0.5 * BIN0 if g0 == 0 else BIN0 * BIN_GROWTH ** (g0 - 1)
            gsum.append(acc_s)
            gcnt.append(acc_n)
            gt.append(math.sqrt(lo_edge * BIN0 * BIN_GROWTH ** b))
            g0, acc_s, acc_n = b + 1, 0.0, 0
    peak, pk = -1, 0.0
    for k in range(len(gt)):
        if gt[k] >= DIFFUSE_MIN_THETA_H:
            break
        if peak < 0 or gsum[k] / gcnt[k] > pk:
            peak, pk = k, gsum[k] / gcnt[k]
    if peak < 0 or not pk > 0.05 * abs(dmean) or not pk > 0.0:
        x[I_RHO_S:I_RHO_S + 3] = 0.01  # no lobe seen
        return np.clip(x, X_LO, X_HI)
    # 3. Half width beyond the peak.
    h, prev_t, prev_v = 1.0, gt[peak], pk
    for k in range(peak + 1, len(gt)):
        vk, t = gsum[k] / gcnt[k], gt[k]
        if vk < 0.5 * pk:
            f = (prev_v - 0.5 * pk) / (prev_v - vk)
            h = math.exp(math.log(prev_t) + f * (math.log(t) - math.log(prev_t)))
            break
        prev_t, prev_v = t, vk
    # 4. Shape samples: the bins nearest the peak, then a stride over the rest.
    half, take, last, last_stride = SHAPE_CAP // 2, 0, -1, 1
    for b in range(NBINS):
        if take + bcnt[b] <= half:
            take, last = take + int(bcnt[b]), b
            continue
        room = half - take
        last_stride = -(-int(bcnt[b]) // room) if room else int(bcnt[b]) + 1
        last = b
        break
    rest = int(bcnt[last + 1:].sum())
    rest_stride = -(-rest // half) if rest > half else 1
    in_last = bins == last
    in_rest = bins > last
    rank_last = np.cumsum(in_last) - 1
    rank_rest = np.cumsum(in_rest) - 1
    chosen = np.where(in_last, rank_last % last_stride == 0,
                      np.where(in_rest, rank_rest % rest_stride == 0, True))
    sel = np.flatnonzero(chosen)[:SHAPE_CAP]
    L = np.stack([g["lx"][sel], g["ly"][sel], g["lz"][sel]], axis=1)
    V = np.stack([g["vx"][sel], g["vy"][sel], g["vz"][sel]], axis=1)
    sg = geometry_from_vectors(L, V)
    terms, y, w = WalterTerms(sg), values[sel], sg["lz"]
    # Width scan; f0 raised while the weights want more than their bound and it helps.
    ssr0, over = _scan_widths(x, h, terms, y, w)
    for _ in range(4):
        if not over > 1.0:
            break
        kept = x.copy()
        x[I_F0] = min(max(x[I_F0] * over, 0.0), 1.0)
        ssr, over = _scan_widths(x, h, terms, y, w)
        if not ssr < ssr0:
            x = kept
            break
        ssr0 = ssr
    return np.clip(x, X_LO, X_HI)


# ---- The two fits ------------------------------------------------------------------------


def run_brdfit(brdfit, data, threads, json_path, extra=()):
    """One `brdfit fit` process: wall seconds and its result JSON."""
    cmd = [brdfit, "fit", data, "-m", "walter", "--threads", str(threads), "-o", json_path, *extra]
    t0 = time.perf_counter()
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        msg = (p.stderr.strip() or p.stdout.strip() or "no output").splitlines()[-1]
        raise InputError(f"{' '.join(cmd)} failed (exit {p.returncode}): {msg}")
    with open(json_path) as fp:
        return wall, json.load(fp)


def brdfit_params(result):
    p = result["params"]
    return np.array(list(p["rho_d"]) + list(p["rho_s"]) + [p["alpha"], p["f0"]], dtype=float)


def run_scipy(data):
    """Read, geometry, start and solve in-process. -> dict of timings and results."""
    t0 = time.perf_counter()
    g, values = load_samples(data)
    t_read = time.perf_counter()
    obj = LogObjective(g, values)
    x0 = data_driven_start(g, values)
    z0 = to_internal(x0)
    t_start = time.perf_counter()
    sol = least_squares(obj.residuals, z0, jac=obj.jacobian, bounds=(Z_LO, Z_HI), method="trf",
                        ftol=FTOL, xtol=XTOL, gtol=GTOL)
    t_end = time.perf_counter()
    r0 = obj.residuals(z0)
    return {"wall": t_end - t0, "read": t_read - t0, "start_s": t_start - t_read, "solve": t_end - t_start,
            "x": to_model(sol.x), "x0": x0, "initial_cost": 0.5 * float(np.dot(r0, r0)),
            "nfev": sol.nfev, "njev": sol.njev, "status": sol.message, "obj": obj, "n": values.shape[0]}


# ---- Reporting -----------------------------------------------------------------------------


def fmt_params(x):
    return ("rho_d " + " ".join(f"{v:.6f}" for v in x[I_RHO_D:I_RHO_D + 3])
            + "  rho_s " + " ".join(f"{v:.6f}" for v in x[I_RHO_S:I_RHO_S + 3])
            + f"  alpha {x[I_ALPHA]:.6f}  f0 {x[I_F0]:.6f}")


def rel_diff(a, b):
    scale = max(abs(a), abs(b))
    return abs(a - b) / scale if scale > 0 else 0.0


def compare(args):
    threads = args.threads
    with tempfile.TemporaryDirectory(prefix="scipy_compare_") as tmp:
        json_path = os.path.join(tmp, "result.json")
        b_walls, result = [], None
        for _ in range(args.brdfit_repeats):
            wall, result = run_brdfit(args.brdfit, args.data, threads, json_path)
            b_walls.append(wall)
        # brdfit solves the starts on a subsample first (its presolve), so its timed
        # result reports the cost where the solve on all samples began; the cost at the
        # data-driven start comes from one untimed run without the presolve.
        _, direct = run_brdfit(args.brdfit, args.data, threads, json_path,
                               ("--presolve", "off", "--max-iterations", "1"))
    s_runs = [run_scipy(args.data) for _ in range(args.scipy_repeats)]
    s = min(s_runs, key=lambda r: r["wall"])
    obj = s["obj"]
    xb, xs = brdfit_params(result), s["x"]
    cost_b, rmse_b = obj.cost_and_log_rmse(xb)
    cost_s, rmse_s = obj.cost_and_log_rmse(xs)
    opt = result["optimizer"]
    b_wall = min(b_walls)
    b_solve = opt["seconds"] + opt.get("presolve", {}).get("seconds", 0.0)

    n, nres = s["n"], s["n"] * CHANNELS
    print(f"data: {args.data}: {n} samples x {CHANNELS} channels = {nres} residuals, {NPAR} parameters, "
          f"model walter (fresnel=schlick), residual log")
    if result.get("samples") != n:
        print(f"warning: brdfit fitted {result.get('samples')} samples, this script {n}")
    print(f"threads: brdfit --threads {threads}; numpy/scipy BLAS threads {os.environ.get('OPENBLAS_NUM_THREADS')}")
    print(f"repeats: brdfit {args.brdfit_repeats}, scipy {args.scipy_repeats} (minimum wall time reported)")
    start_cost = direct["optimizer"]["initial_cost"]
    d0 = rel_diff(s["initial_cost"], start_cost)
    print(f"start: brdfit's data-driven start (init.c, ported): initial cost scipy {s['initial_cost']:.10g}, "
          f"brdfit {start_cost:.10g} (rel. diff {d0:.1e})")
    if d0 > 1e-9:
        print("warning: the ported start differs from brdfit's (init.c changed?): the two fits do not "
              "start from the same point")
    print(f"  start  {fmt_params(s['x0'])}")
    print()
    print(f"{'tool':<8}{'wall s':>9}{'solve s':>9}  {'iterations':<22}{'final cost':>16}{'log RMSE':>16}")
    print(f"{'brdfit':<8}{b_wall:>9.3f}{b_solve:>9.3f}  "
          f"{str(opt['iterations']) + ' it, ' + str(opt['evaluations']) + ' evals':<22}"
          f"{cost_b:>16.10g}{rmse_b:>16.10g}")
    print(f"{'scipy':<8}{s['wall']:>9.3f}{s['solve']:>9.3f}  "
          f"{str(s['njev']) + ' jac, ' + str(s['nfev']) + ' evals':<22}"
          f"{cost_s:>16.10g}{rmse_s:>16.10g}")
    print(f"  brdfit {fmt_params(xb)}")
    print(f"  scipy  {fmt_params(xs)}")
    print(f"  brdfit: {opt['termination']}")
    print(f"  scipy:  {s['status']}")
    print(f"  brdfit wall: the whole process, of which the fit {result['seconds']:.3f} s (start, solve, "
          f"metrics, standard errors; JSON seconds) and Ceres {b_solve:.3f} s (JSON optimizer.seconds, presolve "
          f"included)")
    print(f"  brdfit's JSON: final cost {opt['final_cost']:.10g}, log RMSE {result['metrics']['rmse_log']:.10g}")
    print(f"  scipy wall: read + geometry {s['read']:.3f} s, start {s['start_s']:.3f} s, "
          f"least_squares {s['solve']:.3f} s")
    print()
    print(f"ratio scipy/brdfit wall: {s['wall'] / b_wall:.1f}x")
    print(f"ratio scipy/brdfit solve: {s['solve'] / b_solve:.1f}x")
    dr = rel_diff(rmse_s, rmse_b)
    print(f"log RMSE relative difference: {dr:.2e}" + (" (ok)" if dr <= RMSE_WARN else ""))
    if dr > RMSE_WARN:
        print(f"warning: the two fits differ in log RMSE by more than {RMSE_WARN:.0%}")
    return 0


# ---- Self-check against `brdfit eval` ------------------------------------------------------


def self_check_params():
    """Parameter sets: the example's, pure lobes (rho_d = 0) over a range of alpha, f0."""
    return [
        np.array([0.8, 0.5, 0.2, 0.9, 0.9, 0.9, 0.1, 0.04]),
        np.array([0.0, 0.0, 0.0, 1.0, 0.7, 0.3, 0.01, 0.04]),
        np.array([0.0, 0.0, 0.0, 0.5, 0.6, 0.7, 0.3, 0.9]),
        np.array([0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1e-3, 0.0]),
        np.array([0.3, 0.2, 0.1, 0.4, 0.5, 0.6, 1.0, 1.0]),
    ]


def self_check_dirs(rng, n):
    """Random directions above the horizon (degrees): half uniform, half near the mirror
    direction of L, where the lobe dominates."""
    ti = rng.uniform(0.0, 89.0, n)
    pi_ = rng.uniform(0.0, 360.0, n)
    to = rng.uniform(0.0, 89.0, n)
    po = rng.uniform(0.0, 360.0, n)
    near = np.arange(n) % 2 == 1
    to[near] = np.clip(ti[near] + rng.normal(0.0, 3.0, near.sum()), 0.0, 89.0)
    po[near] = (pi_[near] + 180.0 + rng.normal(0.0, 3.0, near.sum())) % 360.0
    return ti, pi_, to, po


def write_params(path, x):
    """A brdfit parameter file for walter at x (json writes floats round-trip exact)."""
    doc = {"model": "walter", "options": {"fresnel": "schlick"}, "channels": CHANNELS,
           "params": {"rho_d": [float(v) for v in x[I_RHO_D:I_RHO_D + 3]],
                      "rho_s": [float(v) for v in x[I_RHO_S:I_RHO_S + 3]],
                      "alpha": float(x[I_ALPHA]), "f0": float(x[I_F0])}}
    with open(path, "w") as fp:
        json.dump(doc, fp)


def brdfit_eval(brdfit, x, dirs, tmp):
    pfile, dfile, ofile = (os.path.join(tmp, n) for n in ("p.json", "d.csv", "out.csv"))
    write_params(pfile, x)
    with open(dfile, "w") as fp:
        fp.write("theta_i,phi_i,theta_o,phi_o\n")
        for row in zip(*dirs):
            fp.write(",".join(repr(float(v)) for v in row) + "\n")
    cmd = [brdfit, "eval", "--params", pfile, "--dirs", dfile, "-o", ofile]
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        msg = (p.stderr.strip() or "no output").splitlines()[-1]
        raise InputError(f"{' '.join(cmd)} failed (exit {p.returncode}): {msg}")
    out = np.loadtxt(ofile, delimiter=",", skiprows=1, ndmin=2)
    return out[:, 4:4 + CHANNELS]


def jacobian_error(obj, z):
    """Largest relative difference between the analytic Jacobian and central differences."""
    J = obj.jacobian(z)
    worst = 0.0
    for k in range(NPAR):
        h = 1e-6 * max(1.0, abs(z[k]))
        zp, zm = z.copy(), z.copy()
        zp[k] += h
        zm[k] -= h
        fd = (obj.residuals(zp) - obj.residuals(zm)) / (2 * h)
        scale = max(np.max(np.abs(J[:, k])), 1e-300)
        worst = max(worst, float(np.max(np.abs(fd - J[:, k]))) / scale)
    return worst


def self_check(args):
    rng = np.random.default_rng(1)
    dirs = self_check_dirs(rng, 400)
    g = geometry_from_angles(*dirs, libm_trig=True)
    terms = WalterTerms(g)
    worst = 0.0
    with tempfile.TemporaryDirectory(prefix="scipy_compare_") as tmp:
        for x in self_check_params():
            ours = walter_values(terms, x)
            ref = brdfit_eval(args.brdfit, x, dirs, tmp)
            scale = np.maximum(np.abs(ours), np.abs(ref))
            rel = np.where(scale > 0, np.abs(ours - ref) / np.where(scale > 0, scale, 1.0), 0.0)
            worst = max(worst, float(rel.max()))
    print(f"self-check: walter at {dirs[0].size} directions x {len(self_check_params())} parameter sets x "
          f"{CHANNELS} channels against `brdfit eval`: max relative difference {worst:.3e}")
    # The analytic Jacobian of the log residual, against central differences on synthetic data.
    x = self_check_params()[0]
    values = walter_values(terms, x) * np.exp(rng.normal(0.0, 0.05, (dirs[0].size, CHANNELS)))
    obj = LogObjective(g, values)
    inside = [x, np.array([0.3, 0.2, 0.1, 0.6, 0.5, 0.4, 0.02, 0.5]),
              np.array([0.1, 0.1, 0.1, 0.2, 0.3, 0.4, 0.5, 0.9])]  # central differences need room
    jerr = max(jacobian_error(obj, to_internal(xx)) for xx in inside)
    print(f"self-check: analytic Jacobian against central differences: max relative difference {jerr:.3e}")
    ok = worst <= SELF_CHECK_LIMIT and jerr <= 1e-5
    print("self-check: " + ("ok" if ok else f"FAILED (limits {SELF_CHECK_LIMIT:g} values, 1e-05 Jacobian)"))
    return 0 if ok else 1


# ---- Command line --------------------------------------------------------------------------


def parse_args(argv):
    ap = argparse.ArgumentParser(description="Time `brdfit fit -m walter` against scipy least_squares "
                                             "on the same MERL table, model, residual, bounds and start.")
    ap.add_argument("brdfit", help="the brdfit binary")
    ap.add_argument("data", nargs="?", help="a MERL .binary table (not needed with --self-check)")
    ap.add_argument("--threads", type=int, default=os.cpu_count() or 1,
                    help="brdfit --threads, and the BLAS threads of numpy (default: every core)")
    ap.add_argument("--repeats", type=int, default=None,
                    help="runs of each tool, minimum wall time reported (default: brdfit 3, scipy 1)")
    ap.add_argument("--self-check", action="store_true",
                    help="compare this script's walter with `brdfit eval` and exit")
    args = ap.parse_args(argv)
    if args.threads < 1:
        ap.error("--threads needs a positive integer")
    if args.repeats is not None and args.repeats < 1:
        ap.error("--repeats needs a positive integer")
    if not args.self_check and args.data is None:
        ap.error("DATA is required (or --self-check)")
    args.brdfit_repeats = args.repeats or 3
    args.scipy_repeats = args.repeats or 1
    return args


def main(argv):
    args = parse_args(argv)
    try:
        if not (os.path.isfile(args.brdfit) and os.access(args.brdfit, os.X_OK)):
            raise InputError(f"{args.brdfit}: not an executable file")
        if args.self_check:
            return self_check(args)
        read_merl(args.data)  # bad input fails here, before any timing
        return compare(args)
    except InputError as e:
        print(f"scipy_compare: {e}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
