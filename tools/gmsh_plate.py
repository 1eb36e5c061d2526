"""The perforated plate of `pdcontact fracture --case perforation` meshed by gmsh's defaults:
a box 20 x 20 x 2 mm (x, y in [-10, 10] mm, z in [0, 2] mm, metres in the file), tet4 by
default, or its tets split into hexes (--hex), every element of one Physical Volume.

    python3 tools/gmsh_plate.py DIR H [--hex]       # writes DIR/plate.msh
    pdcontact fracture --case perforation --plate-mesh DIR/plate.msh [--spacing DX]

H is gmsh's MeshSizeMax (m); --spacing stays the ball's spacing (default 0.5 mm).
"""
import argparse
import os

import gmsh

ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
ap.add_argument("dir")
ap.add_argument("h", type=float)
ap.add_argument("--hex", action="store_true", help="split the tets into hexes")
args = ap.parse_args()

os.makedirs(args.dir, exist_ok=True)
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.model.add("plate")
gmsh.model.occ.addBox(-0.01, -0.01, 0.0, 0.02, 0.02, 0.002)
gmsh.model.occ.synchronize()
gmsh.model.addPhysicalGroup(3, [1], name="plate")
gmsh.option.setNumber("Mesh.MeshSizeMax", args.h)
if args.hex:
    gmsh.option.setNumber("Mesh.SubdivisionAlgorithm", 2)
gmsh.model.mesh.generate(3)
gmsh.write(os.path.join(args.dir, "plate.msh"))
print(f"{len(gmsh.model.mesh.getNodes()[0])} nodes in {os.path.join(args.dir, 'plate.msh')}")
gmsh.finalize()
