#!/usr/bin/env python3
"""The modulus a particle cloud has under uniaxial stress, and how far its loaded surface layer
sinks, measured with pdcontact itself (docs/VALIDATION.md, "The penalty against the contact's
depth", last paragraph).

A unit cube [0, 1]^3 is meshed by gmsh (hex: structured, DX = 1/n; tet: gmsh's defaults with only
the size set; hexsplit: the same tets split into hexes), cut by the symmetry planes x = 0, y = 0,
z = 0, and pressed by 1 MPa on its top face (E = 1 GPa, nu = 0.25, small kinematics, ADR to 1e-6).
The strain e_zz is the least-squares gradient of u_z over the particles of the cube's central
part; E_eff / E = (1 MPa / E) / |e_zz|. The surface layer: the mean of u_z minus the bulk's
linear fit, in units of |e_zz| times the spacing, for the particles within half a spacing of the
top face (and of each deeper layer), over the central 0.6 x 0.6 of the face.

    python3 -m pip install gmsh==4.15.2 vtk numpy
    python3 tools/bulk_modulus.py tet 0.035 [--seed 2] [--pdcontact target/release/pdcontact]
"""
import argparse
import glob
import os
import subprocess
import sys
import tempfile

import numpy as np


def mesh_cube(kind, h, path, seed):
    import gmsh

    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add("cube")
    v = gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
    gmsh.model.occ.synchronize()
    top = [s[1] for s in gmsh.model.getEntities(2)
           if abs(gmsh.model.occ.getCenterOfMass(2, s[1])[2] - 1) < 1e-9]
    gmsh.model.addPhysicalGroup(3, [v], name="cube")
    gmsh.model.addPhysicalGroup(2, top, name="top")
    if kind == "hex":
        n = int(round(1 / h)) + 1
        for c in gmsh.model.getEntities(1):
            gmsh.model.mesh.setTransfiniteCurve(c[1], n)
        for s in gmsh.model.getEntities(2):
            gmsh.model.mesh.setTransfiniteSurface(s[1])
            gmsh.model.mesh.setRecombine(2, s[1])
        gmsh.model.mesh.setTransfiniteVolume(v)
    else:
        gmsh.option.setNumber("Mesh.MeshSizeMin", h)
        gmsh.option.setNumber("Mesh.MeshSizeMax", h)
        if seed:
            gmsh.option.setNumber("Mesh.RandomSeed", seed)
        if kind == "hexsplit":
            gmsh.option.setNumber("Mesh.SubdivisionAlgorithm", 2)
    gmsh.model.mesh.generate(3)
    gmsh.write(path)
    gmsh.finalize()


SCENE = """[solver]
kind = "adr"
tolerance = 1e-6
max_iterations = 200000
[output]
every = 1000000
[[body]]
name = "cube"
mesh = "{mesh}"
kinematics = "small"
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0
[[symmetry]]
body = "cube"
axis = "x"
[[symmetry]]
body = "cube"
axis = "y"
[[symmetry]]
body = "cube"
axis = "z"
[[load]]
body = "cube"
set = "top"
force = [0.0, 0.0, -1e6]
"""


def read_frame(run):
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy

    files = sorted(glob.glob(os.path.join(run, "frame_*", "cube_particles.vtu")))
    if not files:
        sys.exit(f"{run}: no frame with cube_particles.vtu")
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(files[-1])
    r.Update()
    g = r.GetOutput()
    u = vtk_to_numpy(g.GetPointData().GetArray("displacement"))
    x = vtk_to_numpy(g.GetPoints().GetData()) - u  # reference positions
    volume = vtk_to_numpy(g.GetPointData().GetArray("volume"))
    return x, u, volume


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("kind", choices=["hex", "tet", "hexsplit"])
    ap.add_argument("size", type=float, help="element size h (hex: the spacing 1/n)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--pdcontact", default="target/release/pdcontact")
    ap.add_argument("--keep", help="folder to keep the mesh, scene and run in")
    a = ap.parse_args()
    work = a.keep or tempfile.mkdtemp(prefix="bulk-")
    os.makedirs(work, exist_ok=True)
    mesh = os.path.join(work, "cube.msh")
    mesh_cube(a.kind, a.size, mesh, a.seed)
    scene = os.path.join(work, "scene.toml")
    with open(scene, "w") as f:
        f.write(SCENE.format(mesh=os.path.abspath(mesh)))
    run = os.path.join(work, "run")
    subprocess.run([a.pdcontact, "run", scene, "-o", run, "--quiet"], check=True)
    x, u, volume = read_frame(run)
    # The lattice spacing of the median particle volume (interior particles dominate).
    spacing = float(np.median(volume)) ** (1 / 3)
    for lo, hi in [(0.25, 0.75), (0.35, 0.65)]:
        m = np.all((x > lo) & (x < hi), axis=1)
        A = np.c_[x[m], np.ones(m.sum())]
        cz = np.linalg.lstsq(A, u[m, 2], rcond=None)[0]
        cx = np.linalg.lstsq(A, u[m, 0], rcond=None)[0]
        print(f"central {lo}-{hi}: {m.sum()} particles, e_zz = {cz[2]:.4e}, "
              f"E_eff/E = {-1e-3 / cz[2]:.4f}, nu_eff = {-cx[0] / cz[2]:.4f}")
    m = np.all((x > 0.25) & (x < 0.75), axis=1)
    A = np.c_[x[m], np.ones(m.sum())]
    c = np.linalg.lstsq(A, u[m, 2], rcond=None)[0]
    lat = (x[:, 0] > 0.2) & (x[:, 0] < 0.8) & (x[:, 1] > 0.2) & (x[:, 1] < 0.8)
    depth = 1 - x[:, 2]
    layers = []
    for k in range(4):
        sel = lat & (np.abs(depth - k * spacing) < 0.5 * spacing)
        if sel.sum() == 0:
            continue
        excess = (u[sel, 2] - np.c_[x[sel], np.ones(sel.sum())] @ c) / (c[2] * spacing)
        layers.append(f"{k}: {excess.mean():+.2f}")
    print(f"spacing {spacing:.4g} m; sink below the bulk's line, in |e_zz| spacings, "
          f"by layer under the loaded face: {', '.join(layers)}")


if __name__ == "__main__":
    main()
