"""The notched beam of `pdcontact fracture` (ASTM E399: W = 40 mm, S = 4W, a/W = 0.5) meshed by
gmsh as a user meshes a notched specimen: the notch a slot cut out of the solid, no pre-crack.

The model is the one the study runs: the whole span and 10 mm beyond each support roller
(x in [-90, 90] mm), half the thickness (y in [0, B/2], a symmetry plane at y = 0), z in
[0, W]; the slot x in [-w/2, w/2], z in [0, a], through the thickness. Metres in the file,
tet4 with only the size set (MeshSizeMin = MeshSizeMax = H), or its tets split into hexes
(--hex); every element of one Physical Volume.

    python3 tools/gmsh_beam.py DIR H [--slot W] [--thickness B] [--hex]   # writes DIR/beam.msh
    pdcontact fracture --beam-mesh DIR/beam.msh [--thickness B ...]

--slot defaults to H/4, --thickness to the study's 8 mm (pass the same to the study).
"""
import argparse
import os

import gmsh

ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
ap.add_argument("dir")
ap.add_argument("h", type=float, help="gmsh's MeshSizeMin = MeshSizeMax, m")
ap.add_argument("--slot", type=float, help="the slot's width, m (default H/4)")
ap.add_argument("--thickness", type=float, default=0.008, help="B, m (half is meshed)")
ap.add_argument("--hex", action="store_true", help="split the tets into hexes")
args = ap.parse_args()

W, S, R = 0.04, 0.16, 0.005
half_length = 0.5 * S + 2.0 * R
slot = args.slot if args.slot is not None else 0.25 * args.h
b = 0.5 * args.thickness

os.makedirs(args.dir, exist_ok=True)
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.model.add("beam")
beam = gmsh.model.occ.addBox(-half_length, 0.0, 0.0, 2.0 * half_length, b, W)
notch = gmsh.model.occ.addBox(-0.5 * slot, -0.001, -0.001, slot, b + 0.002, 0.5 * W + 0.001)
out, _ = gmsh.model.occ.cut([(3, beam)], [(3, notch)])
gmsh.model.occ.synchronize()
gmsh.model.addPhysicalGroup(3, [t for d, t in out if d == 3], name="beam")
gmsh.option.setNumber("Mesh.MeshSizeMin", args.h)
gmsh.option.setNumber("Mesh.MeshSizeMax", args.h)
if args.hex:
    gmsh.option.setNumber("Mesh.SubdivisionAlgorithm", 2)
gmsh.model.mesh.generate(3)
path = os.path.join(args.dir, "beam.msh")
gmsh.write(path)
print(f"{len(gmsh.model.mesh.getNodes()[0])} nodes, slot {slot * 1e3:.3g} mm wide, in {path}")
gmsh.finalize()
