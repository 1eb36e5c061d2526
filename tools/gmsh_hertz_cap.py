#!/usr/bin/env python3
"""Mesh the Hertz sphere's quarter cap with gmsh's defaults, as a user would.

    python3 tools/gmsh_hertz_cap.py KIND H A OUT.msh [--scene SCENE.toml] [--shape sector|box]
        [--seed N]

--shape sector (the default): the body of `pdcontact demo`,
meshes/sphere_cap_quarter_shape.geo: a quarter of the shell 2a deep around the
sphere's south pole (R = 1 m), under a surface patch reaching 2a to each side,
its side faces on planes through the centre; the inner spherical face carries
the load. --shape box: the shell R - 3a <= r <= R cut by the box
0 <= x, y <= 3a, z <= 0, loaded on its inner spherical face (docs/VALIDATION.md's
earlier tables). A continuum solution of either body (python3 -m
fe_reference.caps, docs/VALIDATION.md) differs from Hertz by under 1 %: the
box-cut body as a deep one, the demo's body 0.9 % over Hertz's level and 0.8 %
narrower.

Both are meshed with only Mesh.MeshSizeMin = Mesh.MeshSizeMax = H. KIND:
tet4, tet10, or hex (each tet split into four hexes,
Mesh.SubdivisionAlgorithm = 2). The inner spherical face is the physical
surface "top", where the scene puts the load. With --scene, also writes the
Hertz scene for a contact radius A (E = 1 GPa, nu = 0.25, rigid plane,
symmetry planes x = 0 and y = 0, a quarter of P = 4 E* a^3 / 3 on "top").
--seed N (N > 1) sets gmsh's Mesh.RandomSeed = N with Mesh.RandomFactor = 1e-6.
Needs: python3 -m pip install gmsh==4.15.2
"""
import argparse
from pathlib import Path

import gmsh

ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
ap.add_argument("kind", choices=["tet4", "tet10", "hex"])
ap.add_argument("h", type=float)
ap.add_argument("a", type=float)
ap.add_argument("out")
ap.add_argument("--scene")
ap.add_argument("--shape", choices=["sector", "box"], default="sector")
ap.add_argument("--seed", type=int, default=1)
args = ap.parse_args()
a = args.a


def box_cap():
    occ = gmsh.model.occ
    outer = occ.addSphere(0, 0, 0, 1.0)
    inner = occ.addSphere(0, 0, 0, 1.0 - 3 * a)
    shell, _ = occ.cut([(3, outer)], [(3, inner)])
    box = occ.addBox(0, 0, -1.1, 3 * a, 3 * a, 1.1)
    occ.intersect(shell, [(3, box)])
    occ.synchronize()
    volumes = [t for _, t in gmsh.model.getEntities(3)]
    gmsh.model.addPhysicalGroup(3, volumes, name="cap")
    faces = [t for _, t in gmsh.model.getBoundary([(3, v) for v in volumes], oriented=False)]

    def centre_radius(tag):
        x, y, z = occ.getCenterOfMass(2, tag)
        return (x * x + y * y + z * z) ** 0.5

    spheres = [t for t in faces if "Sphere" in gmsh.model.getType(2, t)]
    gmsh.model.addPhysicalGroup(2, [min(spheres, key=centre_radius)], name="top")


if args.shape == "sector":
    geo = Path(__file__).resolve().parent.parent / "meshes" / "sphere_cap_quarter_tet4.geo"
    # The .geo's DefineConstant values give way to -setnumber.
    gmsh.initialize(["gmsh", "-setnumber", "a", repr(a), "-setnumber", "h", repr(args.h)])
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.open(str(geo))
else:
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add("cap")
    box_cap()
gmsh.option.setNumber("Mesh.MeshSizeMin", args.h)
gmsh.option.setNumber("Mesh.MeshSizeMax", args.h)
gmsh.option.setNumber("General.NumThreads", 1)
if args.seed > 1:
    gmsh.option.setNumber("Mesh.RandomSeed", args.seed)
    gmsh.option.setNumber("Mesh.RandomFactor", 1e-6)
if args.kind == "hex":
    gmsh.option.setNumber("Mesh.SubdivisionAlgorithm", 2)
gmsh.model.mesh.generate(3)
if args.kind == "tet10":
    gmsh.model.mesh.setOrder(2)
gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
gmsh.option.setNumber("Mesh.Binary", 1)
gmsh.write(args.out)
gmsh.finalize()

if args.scene:
    youngs, poisson = 1e9, 0.25
    e_star = youngs / (1 - poisson**2)
    load = 4 * e_star * a**3 / 3
    with open(args.scene, "w") as f:
        f.write(f"""# Hertz sphere, a = {a} m (P = {load:.6e} N), quarter cap meshed by gmsh's defaults
[solver]
kind = "adr"
tolerance = 1e-4
max_iterations = 50000
[[body]]
name = "cap"
mesh = "{args.out}"
kinematics = "small"
[body.material]
youngs_modulus = {youngs:e}
poisson_ratio = {poisson}
density = 1000.0
[[body]]
name = "plane"
kind = "rigid"
generator = {{ shape = "plane", point = [0.0, 0.0, -1.0], normal = [0.0, 0.0, 1.0], size = 2.0 }}
[[load]]
body = "cap"
set = "top"
force = [0.0, 0.0, -{load / 4:.6e}]
[[contact]]
slave = "cap"
master = "plane"
radius = 100.0
[[symmetry]]
body = "cap"
axis = "x"
[[symmetry]]
body = "cap"
axis = "y"
""")
