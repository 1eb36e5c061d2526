#!/usr/bin/env python3
"""How much of METHOD.md §7's figures the sampling of a pressure by particles accounts for.

An exact Hertz profile p0 √(1 − r²/a²) is sampled as the PD contact samples it: each particle
of a square lattice of spacing Δ (or of that lattice with every point moved by up to ±JITTER Δ
on each axis) carries the force of the pressure over its own cell (the points nearer to it
than to any other), and its pressure is that force over the cell's area. The figures of
METHOD.md §7 on those pressures (MRE over r ≤ 0.8a against the profile at the particle, the
radius and peak of the same least-squares fit as `pdcontact validate`) are the error that a
solver exact at every cell would still show.

    python3 tools/hertz_sampling.py        # a/Δ = 4.6 .. 15, square and jittered lattices

Needs numpy. Prints one line per a/Δ and lattice (jittered: the mean of three seeds).
"""
import numpy as np

rng = np.random.default_rng(1)


def fit(r, p):
    """Least-squares fit of p0 √(1 − (r/a)²)₊ to (r, p): returns (a, p0).

    As `pdcontact validate` fits (src/output/analysis.rs): a scanned over [rmax/2, 2 rmax],
    p0 linear for each a.
    """
    rmax = r[p > 0].max()
    best = None
    for a in np.linspace(0.5 * rmax, 2.0 * rmax, 2001):
        s = np.sqrt(np.clip(1.0 - (r / a) ** 2, 0.0, None))
        ss = (s * s).sum()
        p0 = (s * p).sum() / ss if ss > 0 else 0.0
        cost = ((p - p0 * s) ** 2).sum()
        if best is None or cost < best[0]:
            best = (cost, a, p0)
    return best[1], best[2]


def sample(a_over_spacing, jitter=0.0, sub=16):
    """MRE, radius error and peak error of the sampled profile (Δ = 1, p0 = 1)."""
    a = a_over_spacing
    half = int(2 * a) + 3
    n = 2 * half + 1
    g = np.arange(-half, half + 1, dtype=float)
    x, y = (c.ravel() for c in np.meshgrid(g, g))
    if jitter > 0:
        x = x + rng.uniform(-jitter, jitter, x.shape)
        y = y + rng.uniform(-jitter, jitter, y.shape)
    # Each cell as the fine points nearest to its particle (among the 3×3 lattice neighbours,
    # which hold the nearest for a jitter under ½).
    f = np.linspace(-half - 0.5, half + 0.5, n * sub, endpoint=False) + 0.5 / sub
    fx, fy = (c.ravel() for c in np.meshgrid(f, f))
    ix = np.rint(fx).astype(int) + half
    iy = np.rint(fy).astype(int) + half
    nearest = np.full(fx.shape, np.inf)
    owner = np.zeros(fx.shape, int)
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            k = np.clip(iy + dy, 0, n - 1) * n + np.clip(ix + dx, 0, n - 1)
            d = (x[k] - fx) ** 2 + (y[k] - fy) ** 2
            closer = d < nearest
            nearest[closer] = d[closer]
            owner[closer] = k[closer]
    da = (f[1] - f[0]) ** 2
    pressure = np.sqrt(np.clip(1.0 - (fx**2 + fy**2) / a**2, 0.0, None))
    force = np.bincount(owner, weights=pressure * da, minlength=len(x))
    area = np.bincount(owner, weights=np.full(len(fx), da), minlength=len(x))
    p = force / area
    r = np.hypot(x, y)
    keep = r < 2 * a
    r, p = r[keep], p[keep]
    inner = r <= 0.8 * a
    mre = np.abs(p[inner] - np.sqrt(1.0 - (r[inner] / a) ** 2)).mean()
    fitted_a, fitted_p0 = fit(r, p)
    return mre, fitted_a / a - 1.0, fitted_p0 - 1.0


if __name__ == "__main__":
    for a_over_spacing in [4.6, 5.5, 8, 12, 15]:
        for jitter in [0.0, 0.35]:
            runs = [sample(a_over_spacing, jitter) for _ in range(1 if jitter == 0 else 3)]
            mre, radius, peak = np.mean(runs, axis=0)
            print(
                f"a/Δ = {a_over_spacing:4.1f}, jitter ±{jitter:.2f}Δ: MRE {100 * mre:.2f} %, "
                f"radius {100 * radius:+.2f} %, peak {100 * peak:+.2f} %"
            )
