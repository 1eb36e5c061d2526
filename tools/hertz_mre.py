#!/usr/bin/env python3
"""Recompute the Hertz sphere figures from the last frame of a pdcontact run.

    python3 tools/hertz_mre.py RUN_DIR --load P --radius R --youngs E --poisson NU [--centre X,Y] [--body NAME]

Reads the `<body>/particles` blocks of the last frame (frame_*.vtm) listed in RUN_DIR/run.pvd
with VTK's own reader (pip install vtk) and prints the mean relative error of METHOD.md section 7: the mean of |p_i - p(r_i)| / p0
over the surface particles that face the contact (outward normal against the contact force)
and lie within r_i <= 0.8 a of the contact centre, loaded or not, with r measured in the
reference configuration; then the radius of the least-squares fit of
p0' sqrt(1 - (r/A)^2) to the facing particles (A and p0' free, as `pdcontact validate` fits it)
and the peak. The pressure is the frame's `contact_pressure` (recovered on the
surface) or, with --field particle_pressure, each particle's own. --centre gives the centre in the plane (default 0,0: a model cut by
symmetry planes through the contact). E* is that of a rigid plane, E / (1 - nu^2). --body reads
one body of a run with several (two deformable spheres: each body's contact force points its
own way, and read together they cancel); every deformable body by default.
"""
import argparse
import math
import re
import sys
from pathlib import Path


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    ap.add_argument("run_dir", type=Path)
    ap.add_argument("--load", type=float, required=True, help="total load P of the whole sphere (N)")
    ap.add_argument("--radius", type=float, required=True)
    ap.add_argument("--youngs", type=float, required=True)
    ap.add_argument("--poisson", type=float, required=True)
    ap.add_argument("--centre", default="0,0")
    ap.add_argument("--body", help="the body to read (default: every deformable body)")
    ap.add_argument("--field", default="contact_pressure",
                    help="the pressure to measure: contact_pressure (recovered on the surface, "
                         "the default) or particle_pressure (each particle's own)")
    args = ap.parse_args()
    try:
        import numpy as np
        import vtk
        from vtk.util.numpy_support import vtk_to_numpy
    except ImportError:
        sys.exit("needs Python's vtk and numpy: pip install vtk")

    pvd = (args.run_dir / "run.pvd").read_text()
    frames = re.findall(r'file="(frame_[0-9]+\.vtm)"', pvd)
    if not frames:
        sys.exit(f"{args.run_dir}/run.pvd lists no frames")
    reader = vtk.vtkXMLMultiBlockDataReader()
    reader.SetFileName(str(args.run_dir / frames[-1]))
    reader.Update()
    # Every deformable body's particles block ("<body>/particles"), one after another.
    grids = []
    root = reader.GetOutput()
    names = []
    for k in range(root.GetNumberOfBlocks()):
        body = root.GetBlock(k)
        name = root.GetMetaData(k).Get(vtk.vtkCompositeDataSet.NAME())
        names.append(name)
        if args.body is not None and name != args.body:
            continue
        if body is not None and body.IsA("vtkMultiBlockDataSet"):
            for j in range(body.GetNumberOfBlocks()):
                if body.GetMetaData(j).Get(vtk.vtkCompositeDataSet.NAME()) == "particles":
                    grids.append(body.GetBlock(j))
    if not grids:
        if args.body is not None:
            sys.exit(f"{frames[-1]} has no deformable body {args.body!r} (bodies: {', '.join(map(str, names))})")
        sys.exit(f"{frames[-1]} has no particles block")

    def field(name):
        return np.concatenate([vtk_to_numpy(g.GetPointData().GetArray(name)) for g in grids])

    # Points are the reference positions (displacement moves them to the deformed ones).
    x = np.concatenate([vtk_to_numpy(g.GetPoints().GetData()) for g in grids]).astype(float)
    p = field(args.field)
    normal = field("normal")
    surface = field("surface") > 0
    force = field("contact_force").sum(axis=0)
    direction = force / np.linalg.norm(force)

    e_star = args.youngs / (1.0 - args.poisson**2)
    a = (3.0 * args.load * args.radius / (4.0 * e_star)) ** (1.0 / 3.0)
    p0 = 3.0 * args.load / (2.0 * math.pi * a * a)

    cx, cy = (float(v) for v in args.centre.split(","))
    loaded = p > 0
    # The contact centre: in the plane given, at the height of the loaded particles.
    centre = np.array([cx, cy, 0.0])
    centre[2] = np.average(x[loaded, 2], weights=p[loaded])
    d = x - centre
    height = np.abs(d @ direction)
    inplane = d - np.outer(d @ direction, direction)
    r = np.linalg.norm(inplane, axis=1)
    spacing = np.median(np.cbrt(field("volume")))
    band = height[loaded].max() + 2.0 * spacing
    facing = surface & (normal @ direction < -0.5) & (height <= band)
    inside = facing & (r <= 0.8 * a)
    theory = p0 * np.sqrt(np.clip(1.0 - (r[inside] / a) ** 2, 0.0, None))
    mre = np.mean(np.abs(p[inside] - theory)) / p0
    print(f"frame {frames[-1]}: a = {a:.5g} m, p0 = {p0:.5g} Pa, {inside.sum()} particles within 0.8a")
    # The fit of output::analysis::fit_elliptic, as the finite-element reference computes it.
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from fe_reference.metrics import fit_elliptic

    fitted, _ = fit_elliptic(r[facing], p[facing])
    print(f"MRE = {100.0 * mre:.2f} %, fitted radius {fitted:.5g} m ({100.0 * (fitted / a - 1.0):+.2f} %), "
          f"peak pressure {p.max():.5g} Pa ({100.0 * (p.max() / p0 - 1.0):+.2f} % of p0)")


if __name__ == "__main__":
    main()
