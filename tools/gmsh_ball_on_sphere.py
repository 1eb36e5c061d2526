#!/usr/bin/env python3
"""A gmsh-default elastic sphere pressed by a rigid ball (or a rigid plane), as a quarter model.

    python3 tools/gmsh_ball_on_sphere.py DIR [H] [--ball RB] [--order 2] [--hex] [--a A]

The sphere (R = 1 m, E = 1 GPa, nu = 0.25) is the lower sphere of tools/gmsh_two_spheres.py:
centred at (0, 0, -1), cut to x >= 0, y >= 0, z >= -1 (its equator a symmetry plane), meshed
by gmsh's defaults with only the size set (H). The ball of radius RB touches it at the origin:
a rigid surface mesh (gmsh's triangles on the whole sphere, size H), free along z and loaded
so that Hertz's contact radius is A (1/R* = 1/R + 1/RB, E* = E/(1 - nu^2)); with --ball 0, a
rigid plane z = 0 instead. Writes sphere.msh, ball.msh and scene.toml (ADR, the sphere the
slave) into DIR and prints the Hertz figures and the command that measures the run.

It separates what the master's curvature does from what the mesh does: the same sphere mesh
under a plane and under balls of decreasing radius, at the same contact radius (docs/VALIDATION.md,
"Two deformable bodies"). CalculiX's figures for the same scenes: `python3 -m fe_reference
--ball RB --loading equator` (tools/fe_reference).
"""
import argparse
import math
import os
import sys

import gmsh

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gmsh_two_spheres import sphere_part  # noqa: E402

SCENE = """# A gmsh sphere (R = 1 m) pressed by a rigid {what} (tools/gmsh_ball_on_sphere.py):
# Hertz a = {a} m, p0 = {p0:.4e} Pa under P = {load:.6e} N (a quarter here), R* = {r_star:.6g} m
[solver]
kind = "adr"
tolerance = 1e-4
max_iterations = 20000
[output]
every = 1000000
[[body]]
name = "ball"
kind = "rigid"
{surface}motion = "free"
free_axis = [0.0, 0.0, 1.0]
[[body]]
name = "sphere"
mesh = "sphere.msh"
kinematics = "small"
{second_order}[body.material]
youngs_modulus = 1.0e9
poisson_ratio = 0.25
density = 1000.0
[[load]]
body = "ball"
force = [0.0, 0.0, {quarter:e}]
[[contact]]
slave = "sphere"
master = "ball"
radius = {penalty}
[[symmetry]]
body = "sphere"
axis = "x"
[[symmetry]]
body = "sphere"
axis = "y"
[[symmetry]]
body = "sphere"
axis = "z"
at = -1.0
keep = "positive"
"""


def ball_surface(path, rb, h):
    """gmsh's triangles on the whole sphere of radius rb centred at (0, 0, rb)."""
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add("ball")
    gmsh.model.occ.addSphere(0, 0, rb, rb)
    gmsh.model.occ.synchronize()
    gmsh.option.setNumber("Mesh.MeshSizeMin", h)
    gmsh.option.setNumber("Mesh.MeshSizeMax", h)
    gmsh.model.mesh.generate(2)
    gmsh.write(path)
    gmsh.finalize()


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("dir")
    p.add_argument("h", nargs="?", type=float, default=0.03)
    p.add_argument("--ball", type=float, default=0.5, help="the ball's radius RB (0: a plane)")
    p.add_argument("--order", type=int, default=1, choices=[1, 2])
    p.add_argument("--hex", action="store_true")
    p.add_argument("--a", type=float, default=0.15)
    p.add_argument("--radius", type=float, default=2290.0, help="penalty radius")
    o = p.parse_args()
    if o.ball < 0.0:
        p.error("--ball must be 0 (a plane) or a radius > 0")
    os.makedirs(o.dir, exist_ok=True)
    nu, youngs, r = 0.25, 1e9, 1.0
    r_star = 1.0 / (1.0 / r + 1.0 / o.ball) if o.ball > 0 else r
    e_star = youngs / (1.0 - nu * nu)
    load = 4.0 * e_star * o.a ** 3 / (3.0 * r_star)
    p0 = 3.0 * load / (2.0 * math.pi * o.a ** 2)
    sphere_part(os.path.join(o.dir, "sphere.msh"), r, -r, True, o.h, o.order, o.hex)
    if o.ball > 0:
        ball_surface(os.path.join(o.dir, "ball.msh"), o.ball, o.h)
        surface, what = 'mesh = "ball.msh"\n', f"ball (RB = {o.ball} m)"
    else:
        surface = ('generator = { shape = "plane", point = [0.0, 0.0, 0.0], '
                   'normal = [0.0, 0.0, -1.0], size = 3.0, divisions = 1 }\n')
        what = "plane"
    second = 'second_order = "all-nodes"\n' if o.order == 2 else ""
    with open(os.path.join(o.dir, "scene.toml"), "w") as f:
        f.write(SCENE.format(what=what, a=o.a, p0=p0, load=load, r_star=r_star, surface=surface,
                             second_order=second, quarter=-load / 4.0, penalty=o.radius))
    print(f"P = {load:.6e} N (whole sphere), R* = {r_star:.6g} m, E* = {e_star:.6e} Pa, "
          f"a = {o.a} m, p0 = {p0:.6e} Pa")
    # hertz_mre.py takes E* as E/(1 - nu^2) and R as R*: the pair's figures.
    print(f"measure: pdcontact run {o.dir}/scene.toml -o {o.dir}/run && python3 tools/hertz_mre.py "
          f"{o.dir}/run --load {load:.6e} --radius {r_star:.9g} --youngs {youngs:g} --poisson {nu}")


if __name__ == "__main__":
    main()
