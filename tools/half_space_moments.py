#!/usr/bin/env python3
"""Energy of the surface layers of a corrected half-space, per strain state and horizon.

A simple cubic lattice fills z <= 0 (periodic in x and y, so every particle of a layer is
alike); surface particles carry half a cell's volume, as a hex mesh's nodes do. The bonds
carry the volume correction of Eq. 10, and the balanced surface correction (METHOD.md §2,
pdcontact's default: geometric mean of the ends, refined from the one-pass factors with
over-relaxation 1.8 until every layer's uniaxial energies are within 1 %) is computed on the
layers. The script then prints, per layer, the corrected energy relative to the bulk value of
an isotropic material with nu = 1/4 under

* the uniaxial strains u = eps x and u = eps z (what the correction matches), and
* the pure shears eps_xy and eps_yz (what it does not).

Usage: python3 tools/half_space_moments.py [m^2 ...]   (default: 8 9 10 13)
Needs numpy.
"""

import itertools
import math
import sys

import numpy as np


def bonds(m):
    """(dz, weight, n) for every lattice bond within delta + r, delta = m spacings."""
    delta, r = m, 0.5
    reach = int(math.ceil(delta + r))
    out = []
    for i, j, k in itertools.product(range(-reach, reach + 1), repeat=3):
        length = math.sqrt(i * i + j * j + k * k)
        if length == 0 or length > delta + r:
            continue
        vc = 1.0 if length <= delta - r else (delta + r - length) / (2 * r)
        # Linearised stretch s = eps n_a^2: a bond's energy is 1/4 c s^2 |xi| v_c V_j.
        out.append((k, vc * length, np.array([i, j, k]) / length))
    return out, reach


def layer_energies(bond_list, layers, r_factors, scale):
    """Uniaxial (x, y, z) and shear (xy, yz, xz) energies per layer, relative to the bulk."""
    uni = np.zeros((layers, 3))
    shear = np.zeros((layers, 3))
    for layer in range(layers):
        for dz, weight, n in bond_list:
            other = layer - dz  # the partner's layer (z' = z + dz <= 0)
            if other < 0:
                continue
            other = min(other, layers - 1)
            volume = 0.5 if other == 0 else 1.0
            factor = 1.0 / math.sqrt((n * n * r_factors[layer] * r_factors[other]).sum())
            a = scale * weight * volume * factor
            n2 = n * n
            uni[layer] += a * n2 * n2
            # Under eps_ab = eps_ba = eps the stretch is 2 eps n_a n_b; the isotropic bulk
            # shear energy (2 mu eps^2 = 0.8 E eps^2) is 4/3 of the uniaxial (0.6 E eps^2).
            shear[layer] += a * 4.0 * np.array(
                [n2[0] * n2[1], n2[1] * n2[2], n2[0] * n2[2]]
            ) / (4.0 / 3.0)
    return uni, shear


def main():
    squares = [int(a) for a in sys.argv[1:]] or [8, 9, 10, 13]
    for m2 in squares:
        m = math.sqrt(m2)
        bond_list, reach = bonds(m)
        layers = 3 * reach
        # c = 12E/(pi delta^4) and W_inf = 3/5 E eps^2 give 1/4 c eps^2 / W_inf = 5/(pi delta^4).
        scale = 5.0 / (math.pi * m**4)
        ones = np.ones((layers, 3))
        raw, _ = layer_energies(bond_list, layers, ones, scale)
        r_factors = raw.copy()  # r = 1/g, starting from the one-pass factors g = W_inf / W
        relaxation, previous = 1.8, math.inf
        for passes in range(1, 61):
            uni, shear = layer_energies(bond_list, layers, r_factors, scale)
            error = np.abs(uni - 1).max()
            if error < 0.01:
                break
            if not error < previous:
                relaxation = 1.0
            previous = error
            r_factors = r_factors * uni**relaxation
        print(f"m = sqrt({m2}): {passes} passes, largest uniaxial error {100 * error:.2f} %")
        print("  layer  uniaxial x  uniaxial z   shear xy   shear yz")
        for layer in range(reach + 1):
            u, s = uni[layer], shear[layer]
            print(
                f"  {layer:5d}  {100 * (u[0] - 1):+9.2f}%  {100 * (u[2] - 1):+9.2f}%"
                f"  {100 * (s[0] - 1):+8.2f}%  {100 * (s[1] - 1):+8.2f}%"
            )


if __name__ == "__main__":
    main()
