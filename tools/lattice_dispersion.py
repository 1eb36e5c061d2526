#!/usr/bin/env python3
"""Plane-wave stiffness of the discrete bond family against the continuum peridynamic one.

For a longitudinal wave u = exp(i k x) along a lattice axis, linearised bond-based PD gives
the restoring force per unit amplitude (the operator's symbol)

    M(k) = sum_j c v_c(|xi|) V_j (n_x^2 / |xi|) (1 - cos k xi_x)

over the simple cubic lattice within delta + dx/2 (Eq. 10's volume correction), and the same
integral over the sphere |xi| < delta for the continuum model. Both are normalised by their own
long-wave limit (the surface correction's bulk factor makes those limits equal), so the ratio
printed is how much stiffer (> 1) or softer (< 1) the discrete bulk is than the continuum one
at the wave numbers a contact of radius a excites (k delta ~ pi delta / a).

Usage: python3 tools/lattice_dispersion.py [m^2 ...]   (default: 8 9 10 13)
Needs numpy.
"""

import itertools
import math
import sys

import numpy as np


def continuum(k_delta, nr=400, nt=400):
    """The continuum symbol with delta = 1 and c = 1, by the midpoint rule."""
    r = (np.arange(nr) + 0.5) / nr
    t = (np.arange(nt) + 0.5) / nt * math.pi
    rr, tt = np.meshgrid(r, t, indexing="ij")
    nx = np.cos(tt)
    f = nx**2 / rr * (1 - np.cos(k_delta * rr * nx)) * 2 * math.pi * rr**2 * np.sin(tt)
    return f.sum() * (1 / nr) * (math.pi / nt)


def discrete(m, k_delta):
    """The lattice symbol (spacing 1, delta = m) and its long-wave limit."""
    delta, r = m, 0.5
    reach = int(math.ceil(delta + r))
    k = k_delta / delta
    symbol = limit = 0.0
    for i, j, l in itertools.product(range(-reach, reach + 1), repeat=3):
        length = math.sqrt(i * i + j * j + l * l)
        if length == 0 or length > delta + r:
            continue
        vc = 1.0 if length <= delta - r else (delta + r - length) / (2 * r)
        w = vc * (i / length) ** 2 / length
        symbol += w * (1 - math.cos(k * i))
        limit += w * (k * i) ** 2 / 2
    return symbol, limit


def main():
    squares = [int(a) for a in sys.argv[1:]] or [8, 9, 10, 13]
    waves = [0.6, 1.2, 2.0]
    print("k delta:      " + "  ".join(f"{kd:7.1f}" for kd in waves))
    for m2 in squares:
        ratios = []
        for kd in waves:
            symbol, limit = discrete(math.sqrt(m2), kd)
            small = 1e-3
            c_limit = continuum(small) / small**2 * kd**2
            ratios.append((symbol / limit) / (continuum(kd) / c_limit))
        print(f"m = sqrt({m2:2d}): " + "  ".join(f"{x:7.4f}" for x in ratios))


if __name__ == "__main__":
    main()
