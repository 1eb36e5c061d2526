#!/usr/bin/env python3
"""How compliant the surface row of a PD body is: a slab pressed between two plates.

    python3 tools/surface_row.py OUT_DIR [--h 0.05] [--mesh FILE] [--pdcontact BIN]

A 2 x 2 x 1 m box (gmsh 4.15.2 defaults, tet4 of size h, or the box mesh FILE with
x, y in [-1, 1] and z in [-0.5, 0.5]) becomes an infinite slab by symmetry planes on its
four sides, and is pressed between two rigid frictionless plates with 1 MPa. The exact
answer is uniaxial strain: eps_z = -sigma (1 + nu)(1 - 2 nu) / (E (1 - nu)) = -8.333e-4
at E = 1 GPa, nu = 1/4, uniform through the thickness. The script writes the scene,
runs `pdcontact run`, and prints, from the last frame, the strain fitted within one
horizon of each plate and in the bulk between, and the displacement of the particles
against the straight line fitted to the bulk's, row by row from the top face, in units of
eps * spacing: 0 everywhere for the exact solution; the surface row's excess is the skin compliance of
docs/VALIDATION.md ("The surface row's compliance").

Needs: python3 -m pip install gmsh==4.15.2 vtk numpy
"""
import argparse
import glob
import json
import subprocess
import sys
from pathlib import Path

import numpy as np

EPS = -1.0e6 * (1.25 * 0.5) / (1.0e9 * 0.75)

SCENE = """[solver]
kind = "adr"
tolerance = 1e-5
max_iterations = 200000

[output]
every = 1000000

[[body]]
name = "block"
mesh = "{mesh}"
kinematics = "small"
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0

[[body]]
name = "floor"
kind = "rigid"
generator = {{ shape = "plane", point = [0.0, 0.0, -0.5], normal = [0.0, 0.0, 1.0], size = 5.0 }}

[[body]]
name = "plate"
kind = "rigid"
generator = {{ shape = "plane", point = [0.0, 0.0, 0.5], normal = [0.0, 0.0, -1.0], size = 5.0 }}
motion = "free"
free_axis = [0.0, 0.0, 1.0]

[[load]]
body = "plate"
force = [0.0, 0.0, -4.0e6]   # 1 MPa on the 2 x 2 m face

[[contact]]
slave = "block"
master = "floor"
radius = 100.0

[[contact]]
slave = "block"
master = "plate"
radius = 100.0
"""
PLANES = "".join(
    f'\n[[symmetry]]\nbody = "block"\naxis = "{a}"\nat = {at}\n' + ('keep = "negative"\n' if at > 0 else "")
    for a in ("x", "y")
    for at in (-1.0, 1.0)
)


def box(path, h):
    import gmsh

    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.occ.addBox(-1, -1, -0.5, 2, 2, 1)
    gmsh.model.occ.synchronize()
    gmsh.option.setNumber("Mesh.MeshSizeMin", h)
    gmsh.option.setNumber("Mesh.MeshSizeMax", h)
    gmsh.model.mesh.generate(3)
    gmsh.option.setNumber("Mesh.Binary", 1)
    gmsh.write(str(path))
    gmsh.finalize()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out", type=Path)
    ap.add_argument("--h", type=float, default=0.05)
    ap.add_argument("--mesh", type=Path)
    ap.add_argument("--pdcontact", default="pdcontact")
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    mesh = args.mesh.resolve() if args.mesh else args.out / f"box_t4_{args.h}.msh"
    if not args.mesh:
        box(mesh, args.h)
    scene = args.out / "scene.toml"
    scene.write_text(SCENE.format(mesh=mesh.resolve()) + PLANES)
    run = args.out / "run"
    subprocess.run([args.pdcontact, "run", str(scene), "-o", str(run), "--quiet"], check=True,
                   stdout=subprocess.DEVNULL)

    import vtk
    from vtk.util.numpy_support import vtk_to_numpy

    frame = sorted(glob.glob(str(run / "frame_*" / "block_particles.vtu")))[-1]
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(frame)
    reader.Update()
    grid = reader.GetOutput()
    x = vtk_to_numpy(grid.GetPoints().GetData())
    u = vtk_to_numpy(grid.GetPointData().GetArray("displacement"))
    case = json.loads(subprocess.run([args.pdcontact, "convert", str(mesh), "-o",
                                      str(args.out / "case"), "--json", "--quiet"],
                                     check=True, capture_output=True, text=True).stdout)
    spacing, horizon = case["spacing"], case["horizon"]
    z0, z1 = x[:, 2].min(), x[:, 2].max()

    def strain(lo, hi):
        m = (x[:, 2] >= lo) & (x[:, 2] <= hi)
        return np.polyfit(x[m, 2], u[m, 2], 1)[0]

    bulk = strain(z0 + horizon, z1 - horizon)
    print(f"{mesh.name}: {len(x)} particles, spacing {spacing:.4f} m, horizon {horizon:.4f} m")
    print(f"strain: bottom layer {strain(z0, z0 + horizon):.4e}, bulk {bulk:.4e}, "
          f"top layer {strain(z1 - horizon, z1):.4e}; exact {EPS:.4e}")
    m = (x[:, 2] >= z0 + horizon) & (x[:, 2] <= z1 - horizon)
    line = np.polyfit(x[m, 2], u[m, 2], 1)
    print("depth/spacing  particles  (u_z - bulk line)/(eps spacing)")
    for k in np.arange(0.0, 4.0, 0.25):
        m = (z1 - x[:, 2] >= k * spacing) & (z1 - x[:, 2] < (k + 0.25) * spacing)
        if m.any():
            off = (u[m, 2] - np.polyval(line, x[m, 2])) / (EPS * spacing)
            print(f"{k:5.2f} {m.sum():9d} {off.mean():9.3f}")


if __name__ == "__main__":
    sys.exit(main())
