"""The three accuracy figures of METHOD.md section 7, as src/output/analysis.rs computes them.

(1) MRE = mean over the slave nodes within r <= 0.8a of |p_i - p(r_i)| / p0, all of
    them, loaded or not; (2) a'/a - 1 from a least-squares fit of p0' sqrt(1 - (r/a')^2)
    to every (r_i, p_i) (p0' and a' both fitted; same scan and golden-section search as
    analysis::fit_elliptic); (3) |sum F - P| / P.
"""
import math

import numpy as np


def _shape(r, a):
    return np.sqrt(np.clip(1.0 - (r / a) ** 2, 0.0, None))


def mre(r, p, problem):
    inside = r <= 0.8 * problem.contact_radius
    if not inside.any():
        return float("nan"), 0
    theory = problem.p0 * _shape(r[inside], problem.contact_radius)
    return float(np.mean(np.abs(p[inside] - theory)) / problem.p0), int(inside.sum())


def fit_elliptic(r, p):
    """(a', p0') minimising sum (p_i - p0' s(r_i; a'))^2; p0' is linear for each a'."""
    loaded = r[p > 0.0]
    if loaded.size == 0:
        return float("nan"), float("nan")
    rmax = float(loaded.max())

    def cost(a):
        s = _shape(r, a)
        ss = float(s @ s)
        p0 = float(s @ p) / ss if ss > 0.0 else 0.0
        return float(np.sum((p - p0 * s) ** 2)), p0

    lo, hi = 0.5 * rmax, 2.0 * rmax
    grid = lo + (hi - lo) * np.arange(201) / 200.0
    best = min(grid, key=lambda a: cost(a)[0])
    step = (hi - lo) / 200.0
    x0, x1 = max(best - step, 1e-12), best + step
    g = 0.5 * (math.sqrt(5.0) - 1.0)
    for _ in range(60):
        a = x1 - g * (x1 - x0)
        b = x0 + g * (x1 - x0)
        if cost(a)[0] < cost(b)[0]:
            x1 = b
        else:
            x0 = a
    a = 0.5 * (x0 + x1)
    return a, cost(a)[1]


def accuracy(r, p, total_force, problem):
    """All three figures plus the fitted values, as a dict."""
    m, n = mre(r, p, problem)
    fa, fp = fit_elliptic(r, p)
    return {
        "mre": m,
        "samples": n,
        "radius_error": fa / problem.contact_radius - 1.0,
        "fitted_radius": fa,
        "fitted_peak": fp,
        "force_balance_error": abs(total_force - problem.load) / problem.load,
    }
