#!/usr/bin/env python3
"""Mesh the Hertz sphere and roller the other ways users mesh them with gmsh.

    python3 tools/gmsh_variants.py OUT_DIR [NAME ... | --roller-sweep]

Writes the meshes of docs/VALIDATION.md, "Meshes made other ways", into OUT_DIR
(all of them, or the NAMEs given). Each is an OpenCASCADE sphere (R = 1 m) or
cylinder (R = 1 m) meshed with Mesh.MeshSizeMin = Mesh.MeshSizeMax = h and one
or two other settings a user might pick: another 3D or 2D algorithm, a random
seed, millimetres, second order, tets split into hexes, an extruded disc. Then:

    pdcontact validate --mesh OUT_DIR/NAME.EXT [--case roller]
    pdcontact convert OUT_DIR/torus_t4.msh -o DIR --json   # the surface on other shapes

CDB versions: python3 tools/mesh_to_cdb.py OUT_DIR/t4_hxt_06.msh t4_hxt_06.cdb
Needs: python3 -m pip install gmsh==4.15.2
"""
import sys
from pathlib import Path

import gmsh

# name: (shape, h, options, file suffix)
#   shape: ("sphere", R, centre) | ("cylinder", R, length) | ("extruded", R, length, quads)
#          | ("torus", R, r) | ("box",) | ("box_with_hole",): shapes for the eigenvalue
#          surface and the surface correction only
VARIANTS = {
    "t4_hxt_06": (("sphere", 1.0, (0, 0, 0)), 0.06, {"Mesh.Algorithm3D": 10}, "msh"),
    "t4_frontal_05": (("sphere", 1.0, (0, 0, 0)), 0.05, {"Mesh.Algorithm3D": 4}, "inp"),
    "t4_del2d_06_s7": (("sphere", 1.0, (0, 0, 0)), 0.06,
                       {"Mesh.Algorithm": 5, "Mesh.RandomSeed": 7}, "msh22"),
    "t4_mm_r25": (("sphere", 25.0, (10, 20, 30)), 1.25, {}, "msh22"),
    "t10_06": (("sphere", 1.0, (0, 0, 0)), 0.06, {"Mesh.ElementOrder": 2}, "inp"),
    "hx_hxt_015": (("sphere", 1.0, (0, 0, 0)), 0.15,
                   {"Mesh.Algorithm3D": 10, "Mesh.SubdivisionAlgorithm": 2}, "msh"),
    "roller_t4_05": (("cylinder", 1.0, 0.5), 0.05, {}, "inp"),
    "cyl_z_L03_h005": (("cylinder", 1.0, 0.3), 0.05, {}, "msh"),
    "cyl_z_L05_h006": (("cylinder", 1.0, 0.5), 0.06, {}, "msh"),
    "cyl_z_L05_h004": (("cylinder", 1.0, 0.5), 0.04, {}, "msh"),
    "ext_1": (("extruded", 1.0, 0.3, True), 0.05, {}, "inp"),
    "ext_0": (("extruded", 1.0, 0.3, False), 0.05, {}, "inp"),
    "torus_t4": (("torus", 1.0, 0.35), 0.06, {}, "msh"),
    "box_t4": (("box",), 0.08, {}, "msh"),
    "boxhole_t4": (("box_with_hole",), 0.08, {}, "msh"),
    "boxhole_hx": (("box_with_hole",), 0.16, {"Mesh.SubdivisionAlgorithm": 2}, "msh"),
}

# `--roller-sweep`: the 0.3 m cylinder at eight sizes, gmsh's default seed and seed 3
# (docs/VALIDATION.md, "Eight sizes, two seeds").
SWEEP = {
    f"roller_sweep_{h}_{seed}": (
        ("cylinder", 1.0, 0.3),
        h,
        {"Mesh.RandomSeed": seed, "Mesh.RandomFactor": 1e-6} if seed else {},
        "msh",
    )
    for h in (0.07, 0.065, 0.06, 0.055, 0.05, 0.045, 0.04, 0.035)
    for seed in (0, 3)
}


def build(shape):
    occ = gmsh.model.occ
    if shape[0] == "sphere":
        _, r, c = shape
        occ.addSphere(*c, r)
    elif shape[0] == "torus":
        _, big, small = shape
        occ.addTorus(0, 0, 0, big, small)
    elif shape[0] == "box":
        occ.addBox(-1, -1, -0.5, 2, 2, 1)
    elif shape[0] == "box_with_hole":
        box = occ.addBox(-1, -1, -0.5, 2, 2, 1)
        hole = occ.addCylinder(0, 0, -0.6, 0, 0, 1.2, 0.4)
        occ.cut([(3, box)], [(3, hole)])
    elif shape[0] == "cylinder":
        _, r, length = shape
        occ.addCylinder(0, 0, -length / 2, 0, 0, length, r)
    else:
        _, r, length, quads = shape
        disc = occ.addDisk(0, 0, 0, r, r)
        occ.extrude([(2, disc)], 0, 0, length, numElements=[6], recombine=quads)
        occ.synchronize()
        if quads:
            gmsh.model.mesh.setRecombine(2, disc)
    occ.synchronize()


def write(name, out_dir):
    shape, h, options, suffix = {**VARIANTS, **SWEEP}[name]
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add(name)
    build(shape)
    gmsh.option.setNumber("Mesh.MeshSizeMin", h)
    gmsh.option.setNumber("Mesh.MeshSizeMax", h)
    for key, value in options.items():
        gmsh.option.setNumber(key, value)
    gmsh.model.mesh.generate(3)
    path = out_dir / f"{name}.{'msh' if suffix.startswith('msh') else suffix}"
    if suffix == "msh":
        gmsh.option.setNumber("Mesh.Binary", 1)
    elif suffix == "msh22":
        gmsh.option.setNumber("Mesh.MshFileVersion", 2.2)
    gmsh.write(str(path))
    gmsh.finalize()
    print(path)


def main():
    if len(sys.argv) < 2 or sys.argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        sys.exit(0 if len(sys.argv) > 1 else 2)
    out_dir = Path(sys.argv[1])
    out_dir.mkdir(parents=True, exist_ok=True)
    names = sys.argv[2:] or list(VARIANTS)
    if names == ["--roller-sweep"]:
        names = list(SWEEP)
    unknown = [n for n in names if n not in VARIANTS and n not in SWEEP]
    if unknown:
        sys.exit(f"unknown variant(s) {', '.join(unknown)}; expected some of {', '.join(VARIANTS)}")
    for name in names:
        write(name, out_dir)


if __name__ == "__main__":
    main()
