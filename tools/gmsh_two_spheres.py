#!/usr/bin/env python3
"""Two gmsh-default spheres pressed together, as quarter models (docs/VALIDATION.md,
"Two deformable bodies"): the upper sphere of radius R1 centred at (0, 0, R1) and cut to
x >= 0, y >= 0; the lower of radius R2 centred at (0, 0, -R2) and cut to x >= 0, y >= 0,
z >= -R2 (its equator becomes a symmetry plane). Both touch the origin. Each is meshed by
gmsh's defaults with only the size set (MeshSizeMin = MeshSizeMax = H, the upper at H1 if
given). Writes upper.msh, lower.msh and scene.toml (ADR, two passes; the load on the upper
sphere such that Hertz's contact radius for the pair is a = A (METHOD.md §7:
1/R* = 1/R1 + 1/R2, 1/E* = (1 - nu^2)(1/E1 + 1/E2)); the penalty radius that `run` advises
for it, 2290 m for two identical 1 m spheres at a = 0.3 m) into DIR, and prints the Hertz
figures.

    python3 tools/gmsh_two_spheres.py DIR [H] [--order 2] [--hex] [--r1 R1] [--r2 R2]
        [--e1 E1] [--e2 E2] [--h1 H1] [--a A] [--radius PENALTY]

--order 2 meshes tet10 and writes second_order = "all-nodes" on both bodies; --hex splits
gmsh's tets into hexes (Mesh.SubdivisionAlgorithm = 2). Defaults: H = 0.05, R1 = R2 = 1 m,
E1 = E2 = 1 GPa, nu = 0.25, a = 0.3 m.
"""
import argparse
import math
import os

import gmsh

BODY = """[[body]]
name = "{name}"
mesh = "{name}.msh"
kinematics = "small"
{second_order}[body.material]
youngs_modulus = {e:e}
poisson_ratio = 0.25
density = 1000.0
"""

SCENE = """# Two deformable gmsh spheres, quarter models (tools/gmsh_two_spheres.py): R1 = {r1} m,
# R2 = {r2} m, E1 = {e1:e} Pa, E2 = {e2:e} Pa; Hertz a = {a} m, p0 = {p0:.4e} Pa under
# P = {load:.6e} N on the whole sphere (a quarter here)
[solver]
kind = "adr"
tolerance = 1e-4
max_iterations = 20000
[output]
every = 1000000
{upper}{lower}[[load]]
body = "upper"
force = [0.0, 0.0, {quarter:e}]
[[contact]]
slave = "upper"
master = "lower"
radius = {penalty}
two_pass = true
[[symmetry]]
body = "upper"
axis = "x"
[[symmetry]]
body = "upper"
axis = "y"
[[symmetry]]
body = "lower"
axis = "x"
[[symmetry]]
body = "lower"
axis = "y"
[[symmetry]]
body = "lower"
axis = "z"
at = {zcut}
keep = "positive"
"""


def sphere_part(path, r, cz, eighth, h, order, hexes):
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add(os.path.basename(path))
    s = gmsh.model.occ.addSphere(0, 0, cz, r)
    zmin = cz if eighth else cz - 1.5 * r
    box = gmsh.model.occ.addBox(0, 0, zmin, 2 * r, 2 * r, cz + 1.5 * r - zmin)
    gmsh.model.occ.intersect([(3, s)], [(3, box)])
    gmsh.model.occ.synchronize()
    gmsh.option.setNumber("Mesh.MeshSizeMin", h)
    gmsh.option.setNumber("Mesh.MeshSizeMax", h)
    if hexes:
        gmsh.option.setNumber("Mesh.SubdivisionAlgorithm", 2)
    gmsh.model.mesh.generate(3)
    if order == 2:
        gmsh.model.mesh.setOrder(2)
    n = len(gmsh.model.mesh.getNodes(3, -1, True, False)[0])
    gmsh.write(path)
    gmsh.finalize()
    return n


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("dir")
    p.add_argument("h", nargs="?", type=float, default=0.05)
    p.add_argument("--order", type=int, default=1, choices=[1, 2])
    p.add_argument("--hex", action="store_true")
    p.add_argument("--r1", type=float, default=1.0)
    p.add_argument("--r2", type=float, default=1.0)
    p.add_argument("--e1", type=float, default=1e9)
    p.add_argument("--e2", type=float, default=1e9)
    p.add_argument("--h1", type=float, default=None)
    p.add_argument("--a", type=float, default=0.3)
    p.add_argument("--radius", type=float, default=2290.0, help="penalty radius")
    o = p.parse_args()
    os.makedirs(o.dir, exist_ok=True)
    nu = 0.25
    r_star = 1.0 / (1.0 / o.r1 + 1.0 / o.r2)
    e_star = 1.0 / ((1.0 - nu * nu) * (1.0 / o.e1 + 1.0 / o.e2))
    load = 4.0 * e_star * o.a ** 3 / (3.0 * r_star)
    p0 = 3.0 * load / (2.0 * math.pi * o.a ** 2)
    sphere_part(os.path.join(o.dir, "upper.msh"), o.r1, o.r1, False, o.h1 or o.h, o.order, o.hex)
    sphere_part(os.path.join(o.dir, "lower.msh"), o.r2, -o.r2, True, o.h, o.order, o.hex)
    second = 'second_order = "all-nodes"\n' if o.order == 2 else ""
    with open(os.path.join(o.dir, "scene.toml"), "w") as f:
        f.write(SCENE.format(
            r1=o.r1, r2=o.r2, e1=o.e1, e2=o.e2, a=o.a, p0=p0, load=load,
            upper=BODY.format(name="upper", second_order=second, e=o.e1),
            lower=BODY.format(name="lower", second_order=second, e=o.e2),
            quarter=-load / 4.0, penalty=o.radius, zcut=-o.r2))
    print(f"P = {load:.6e} N (whole sphere), R* = {r_star:.6g} m, E* = {e_star:.6e} Pa, a = {o.a} m, p0 = {p0:.6e} Pa")


if __name__ == "__main__":
    main()
