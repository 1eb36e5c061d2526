#!/usr/bin/env python3
"""A gmsh sphere pressed into a block of the same material, as quarter models (issue 40: a
block large enough to stand for a half-space). The upper body is a sphere of radius R
centred at (0, 0, R), cut to x >= 0, y >= 0, meshed by gmsh's defaults with only the size
set (MeshSizeMin = MeshSizeMax = H1, H by default), as tools/gmsh_two_spheres.py meshes
it. The lower body is the quarter block 0 <= x <= L/2, 0 <= y <= L/2, -D <= z <= 0 (an
L x L x D block) whose corner at the origin touches the sphere's pole; its bottom z = -D is
a symmetry plane (it holds u_z = 0 there: the block rests on a frictionless support).
The block is meshed with size H within FINE of the contact point (a gmsh Distance field on
the corner vertex and a Threshold field on it), growing linearly with slope GROWTH up to
HMAX, nothing else set; --uniform meshes it at H throughout instead. --order 2 meshes both
bodies tet10 and writes second_order = "all-nodes" on both; --hex splits gmsh's tets into
hexes (Mesh.SubdivisionAlgorithm = 2), as tools/gmsh_two_spheres.py does.

Writes upper.msh, lower.msh and scene.toml (ADR, two passes; the load on the upper sphere,
spread over it by volume, such that Hertz's contact radius for a sphere on a half-space of
the same material is a = A (METHOD.md section 7: R* = R, 1/E* = 2(1 - nu^2)/E); the
penalty radius that `pdcontact run --check` advises for it: 4492 m for R = 1 m, E = 1 GPa,
a = 0.3 m, where gmsh_two_spheres.py's pair gets 2290 m) into DIR, and prints the Hertz
figures and the node counts of the two meshes.

    python3 tools/gmsh_sphere_block.py DIR [H] [--l L] [--d D] [--hmax HMAX] [--fine FINE]
        [--growth G] [--uniform] [--h1 H1] [--r R] [--e E] [--a A] [--radius PENALTY]
        [--order 2 | --hex]

Defaults: H = 0.05, L = D = 4 m, HMAX = 0.3, FINE = 1.5a, G = 0.1, R = 1 m, E = 1 GPa,
nu = 0.25, a = 0.3 m, penalty radius 4492 m. Compare with Hertz (R2 = 1e12 for the flat):

    two_spheres DIR/scene.toml OUT P R 1e12 E E

Beside scene.toml it writes one_pass.toml (the same with two_pass = false: the sphere the
slave, the block's pressure its reactions) and plane.toml (the sphere alone on a rigid plane
at z = 0 under twice the load, which gives the same a: E* doubles), compared with
`two_spheres DIR/plane.toml OUT 2P R 1e12 E 1e30`.
"""
import argparse
import math
import os
import sys

import gmsh

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gmsh_two_spheres import BODY, sphere_part  # noqa: E402  (the same upper sphere)

SCENE = """# A gmsh sphere pressed into a block of the same material, quarter models
# (tools/gmsh_sphere_block.py): R = {r} m, block {l} x {l} x {d} m (the quarter
# x <= {hl}, y <= {hl}, z >= -{d}), E = {e:e} Pa; {mesh}.
# Hertz for a sphere on a half-space: a = {a} m, p0 = {p0:.4e} Pa under P = {load:.6e} N on
# the whole sphere (a quarter here)
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

SCENE_PLANE = """# The sphere of scene.toml alone on a rigid plane (tools/gmsh_sphere_block.py): R = {r} m,
# E = {e:e} Pa; {mesh}. Hertz for a sphere on a rigid plane: a = {a} m under
# P = {load:.6e} N on the whole sphere (a quarter here), twice the block's load
[solver]
kind = "adr"
tolerance = 1e-4
max_iterations = 20000
[output]
every = 1000000
{upper}[[body]]
name = "floor"
kind = "rigid"
generator = {{ shape = "plane", point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0], size = 4.0, divisions = 1 }}
[[load]]
body = "upper"
force = [0.0, 0.0, {quarter:e}]
[[contact]]
slave = "upper"
master = "floor"
radius = {penalty}
[[symmetry]]
body = "upper"
axis = "x"
[[symmetry]]
body = "upper"
axis = "y"
"""


def block_part(path, half, depth, h, hmax, fine, growth, uniform, order, hexes):
    """The quarter block [0, half] x [0, half] x [-depth, 0], size h within `fine` of the
    origin growing with slope `growth` to hmax (or h throughout when `uniform`)."""
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add(os.path.basename(path))
    gmsh.model.occ.addBox(0, 0, -depth, half, half, depth)
    gmsh.model.occ.synchronize()
    if uniform:
        gmsh.option.setNumber("Mesh.MeshSizeMin", h)
        gmsh.option.setNumber("Mesh.MeshSizeMax", h)
    else:
        corner = gmsh.model.getEntitiesInBoundingBox(-1e-9, -1e-9, -1e-9, 1e-9, 1e-9, 1e-9, 0)
        if len(corner) != 1:
            raise RuntimeError(f"expected one vertex at the origin, found {corner}")
        f = gmsh.model.mesh.field
        d = f.add("Distance")
        f.setNumbers(d, "PointsList", [corner[0][1]])
        t = f.add("Threshold")
        f.setNumber(t, "InField", d)
        f.setNumber(t, "SizeMin", h)
        f.setNumber(t, "SizeMax", hmax)
        f.setNumber(t, "DistMin", fine)
        f.setNumber(t, "DistMax", fine + (hmax - h) / growth)
        f.setAsBackgroundMesh(t)
        for opt in ("Mesh.MeshSizeExtendFromBoundary", "Mesh.MeshSizeFromPoints",
                    "Mesh.MeshSizeFromCurvature"):
            gmsh.option.setNumber(opt, 0)
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
    p.add_argument("h", nargs="?", type=float, default=0.05, help="size at the contact (m)")
    p.add_argument("--l", type=float, default=4.0, help="block width L (the quarter is L/2 wide)")
    p.add_argument("--d", type=float, default=None, help="block depth D (default L)")
    p.add_argument("--hmax", type=float, default=0.3, help="the block's size far from the contact")
    p.add_argument("--fine", type=float, default=None, help="size H within this distance (default 1.5a)")
    p.add_argument("--growth", type=float, default=0.1, help="slope of the size beyond FINE")
    p.add_argument("--uniform", action="store_true", help="mesh the block at H throughout")
    p.add_argument("--h1", type=float, default=None, help="the sphere's size (default H)")
    p.add_argument("--r", type=float, default=1.0)
    p.add_argument("--e", type=float, default=1e9)
    p.add_argument("--a", type=float, default=0.3)
    p.add_argument("--order", type=int, default=1, choices=[1, 2])
    p.add_argument("--hex", action="store_true")
    p.add_argument("--radius", type=float, default=4492.0, help="penalty radius (what `run --check` advises for a = 0.3 m)")
    o = p.parse_args()
    os.makedirs(o.dir, exist_ok=True)
    depth = o.d if o.d is not None else o.l
    fine = o.fine if o.fine is not None else 1.5 * o.a
    nu = 0.25
    r_star = o.r
    e_star = o.e / (2.0 * (1.0 - nu * nu))
    load = 4.0 * e_star * o.a ** 3 / (3.0 * r_star)
    p0 = 3.0 * load / (2.0 * math.pi * o.a ** 2)
    nu_ = sphere_part(os.path.join(o.dir, "upper.msh"), o.r, o.r, False, o.h1 or o.h, o.order, o.hex)
    nl = block_part(os.path.join(o.dir, "lower.msh"), 0.5 * o.l, depth, o.h, o.hmax, fine,
                    o.growth, o.uniform, o.order, o.hex)
    kind = "tet10" if o.order == 2 else "hexes from tets" if o.hex else "tet4"
    mesh = (f"sphere {kind} H = {o.h1 or o.h} m, block {kind} " +
            (f"H = {o.h} m" if o.uniform else
             f"H = {o.h} m within {fine:g} m of the contact, slope {o.growth:g} to {o.hmax} m"))
    second = 'second_order = "all-nodes"\n' if o.order == 2 else ""
    with open(os.path.join(o.dir, "scene.toml"), "w") as f:
        f.write(SCENE.format(
            r=o.r, l=o.l, hl=0.5 * o.l, d=depth, e=o.e, a=o.a, p0=p0, load=load, mesh=mesh,
            upper=BODY.format(name="upper", second_order=second, e=o.e),
            lower=BODY.format(name="lower", second_order=second, e=o.e),
            quarter=-load / 4.0, penalty=o.radius, zcut=-depth))
    # The same scene with one pass, and the sphere alone on a rigid plane under 2P.
    with open(os.path.join(o.dir, "scene.toml")) as f:
        scene = f.read()
    with open(os.path.join(o.dir, "one_pass.toml"), "w") as f:
        f.write(scene.replace("two_pass = true", "two_pass = false"))
    with open(os.path.join(o.dir, "plane.toml"), "w") as f:
        f.write(SCENE_PLANE.format(
            r=o.r, e=o.e, a=o.a, load=2.0 * load, mesh=mesh,
            upper=BODY.format(name="upper", second_order=second, e=o.e),
            quarter=-load / 2.0, penalty=o.radius))
    print(f"P = {load:.6e} N (whole sphere), R* = {r_star:.6g} m, E* = {e_star:.6e} Pa, a = {o.a} m, "
          f"p0 = {p0:.6e} Pa; nodes: upper {nu_}, lower {nl}")


if __name__ == "__main__":
    main()
