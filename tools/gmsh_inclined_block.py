#!/usr/bin/env python3
"""The block cut at 30 degrees to its load (docs/FRACTURE.md, "The 30° crack against
CalculiX") meshed by gmsh's defaults instead of the box generator: half of a 1 x 1 x 2 m
block, x in [-0.5, 0.5], y in [0, 0.5], z in [0, 1] (symmetry planes y = 0 and z = 0), with
Physical Surfaces "top" (z = 1) and "bottom" (z = 0); only the size set
(MeshSizeMin = MeshSizeMax = H). Writes block.msh, scene.toml (the pre-crack through
(0, y, Z0) whose normal leans 30 degrees from the load, the block its own master) and
whole.toml (the same block uncut) into DIR.

    python3 tools/gmsh_inclined_block.py DIR [H] [--order 2] [--hex] [--z0 Z0]
    pdcontact run DIR/scene.toml -o DIR/cut && pdcontact run DIR/whole.toml -o DIR/whole
    python3 tools/fe_inclined_crack.py --frames DIR/cut DIR/whole --z0 Z0

--order 2 meshes tet10 and makes every node a particle (second_order = "all-nodes"); --hex
splits gmsh's tets into hexes (Mesh.SubdivisionAlgorithm = 2). Defaults: H = 0.05,
Z0 = 0.5125 (the height at which the study cuts the lattice at spacing 0.05 m).
"""
import argparse
import math
import os

import gmsh

SCENE = """# The block cut at 30 degrees to its load, gmsh-default mesh (tools/gmsh_inclined_block.py)
[solver]
kind = "adr"
tolerance = 1e-6
max_iterations = 100000
[output]
every = 1000000
[[body]]
name = "block"
mesh = "block.msh"
kinematics = "small"
{second_order}[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0
[[symmetry]]
body = "block"
axis = "y"
[[symmetry]]
body = "block"
axis = "z"
[[constraint]]
body = "block"
set = "top"
fix = ["x"]
[[constraint]]
body = "block"
set = "bottom"
fix = ["x"]
[[load]]
body = "block"
set = "top"
force = [0, 0, -5e5]
"""

CRACK = """[[precrack]]
body = "block"
point = [0, 0.25, {z0}]
normal = [{s}, 0, {c}]
along = [0, 1, 0]
size = [2, 3]
[[contact]]
slave = "block"
master = "block"
"""


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dir")
    ap.add_argument("h", nargs="?", type=float, default=0.05)
    ap.add_argument("--order", type=int, default=1, choices=[1, 2])
    ap.add_argument("--hex", action="store_true")
    ap.add_argument("--z0", type=float, default=0.5125)
    args = ap.parse_args()
    os.makedirs(args.dir, exist_ok=True)
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add("block")
    vol = gmsh.model.occ.addBox(-0.5, 0.0, 0.0, 1.0, 0.5, 1.0)
    gmsh.model.occ.synchronize()
    top, bottom = [], []
    for dim, tag in gmsh.model.getBoundary([(3, vol)], oriented=False):
        z = gmsh.model.occ.getCenterOfMass(dim, tag)[2]
        if abs(z - 1.0) < 1e-9:
            top.append(tag)
        elif abs(z) < 1e-9:
            bottom.append(tag)
    gmsh.model.addPhysicalGroup(3, [vol], name="block")
    gmsh.model.addPhysicalGroup(2, top, name="top")
    gmsh.model.addPhysicalGroup(2, bottom, name="bottom")
    gmsh.option.setNumber("Mesh.MeshSizeMin", args.h)
    gmsh.option.setNumber("Mesh.MeshSizeMax", args.h)
    if args.hex:
        gmsh.option.setNumber("Mesh.SubdivisionAlgorithm", 2)
    gmsh.model.mesh.generate(3)
    if args.order == 2:
        gmsh.model.mesh.setOrder(2)
    gmsh.write(os.path.join(args.dir, "block.msh"))
    gmsh.finalize()
    second = 'second_order = "all-nodes"\n' if args.order == 2 else ""
    s, c = math.sin(math.radians(30)), math.cos(math.radians(30))
    scene = SCENE.format(second_order=second)
    with open(os.path.join(args.dir, "whole.toml"), "w") as f:
        f.write(scene)
    with open(os.path.join(args.dir, "scene.toml"), "w") as f:
        f.write(scene + CRACK.format(z0=args.z0, s=s, c=c))
    print(f"wrote {args.dir}/block.msh, scene.toml and whole.toml (H = {args.h}, cut at z0 = {args.z0})")


if __name__ == "__main__":
    main()
