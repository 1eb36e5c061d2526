#!/usr/bin/env python3
"""CalculiX reference for the block cut at 30 degrees to its load (docs/FRACTURE.md,
"Contact on new surfaces"), compared with pdcontact's run of the same scene.

The scene of `pdcontact fracture --case closing` (its `inclined` and `inclined_whole` runs):
half of a 1 x 1 x 2 m block, x in [-0.5, 0.5], y in [0, 0.5] (symmetry y = 0), z in [0, 1]
(symmetry z = 0), E = 1 GPa, nu = 1/4, 1 MPa on its top face z = 1, the top and the bottom
faces held along x; cut across its whole section by the plane through (0, y, z0) whose
normal (sin 30, 0, cos 30) leans 30 degrees from the load; the faces frictionless.

The finite-element model: the two parts of the block on either side of the cut, each a
mapped grid of 8-node hexahedra with incompatible modes (C3D8I, which do not lock in the
bending the upper part takes), their nodes coincident on the cut; frictionless surface-to-
surface penalty contact between them (CalculiX's default without *FRICTION); the same block
whole (the parts' nodes merged) for the intact figures. Printed side by side with pdcontact:
the top face's mean displacement along z, whole and cut, and the slide: the jump of the
displacement along the cut (in the x-z plane) across it, over the faces away from the
block's sides (|x| < 0.4 m, y < 0.4 m): CalculiX's at the coincident node pairs of the two
faces, pdcontact's from each side's particles within two spacings of the cut, fitted as a
line in the distance from it and taken at the cut.

    pdcontact fracture --case closing --json > closing.json     # [--spacing 0.025]
    python3 tools/fe_inclined_crack.py closing.json [more.json ...] [--n 20 30] [--workdir W]

The same on a gmsh mesh (tools/gmsh_inclined_block.py), from the runs' last frames:

    python3 tools/fe_inclined_crack.py --frames CUT WHOLE [--z0 0.5125] [--n 20] [--nu 0.3]

Needs ccx (apt-get install calculix-ccx) and numpy; --frames also python3 vtk.
"""
import argparse
import glob
import json
import math
import os
import shutil
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fe_reference import ccx, deck  # noqa: E402

E, NU, STRESS = 1e9, 0.25, 1e6
TILT = math.radians(30.0)
ALONG = np.array([math.cos(TILT), 0.0, -math.sin(TILT)])  # down the slope, in x-z


def crack_z(x, z0):
    """Height of the cut at x."""
    return z0 - x * math.tan(TILT)


def parts(n, z0):
    """The two parts as mapped hexahedral grids: nodes (N x 3) and connectivity, the lower
    part's nodes first. `n` elements along x; half as many along y and along z in each
    part. Returns nodes, (lower conn, upper conn), and each part's node index grid."""
    nx, ny, nz = n, max(n // 2, 1), max(n // 2, 1)
    xs = np.linspace(-0.5, 0.5, nx + 1)
    ys = np.linspace(0.0, 0.5, ny + 1)
    ts = np.linspace(0.0, 1.0, nz + 1)
    nodes, grids, conns = [], [], []
    for part in range(2):
        base = sum(len(p) for p in nodes)
        idx = np.arange((nx + 1) * (ny + 1) * (nz + 1)).reshape(nx + 1, ny + 1, nz + 1) + base
        pts = []
        for x in xs:
            zc = crack_z(x, z0)
            for y in ys:
                for t in ts:
                    z = t * zc if part == 0 else zc + t * (1.0 - zc)
                    pts.append((x, y, z))
        nodes.append(np.array(pts))
        grids.append(idx)
        c = []
        for i in range(nx):
            for j in range(ny):
                for k in range(nz):
                    c.append([idx[i, j, k], idx[i + 1, j, k], idx[i + 1, j + 1, k], idx[i, j + 1, k],
                              idx[i, j, k + 1], idx[i + 1, j, k + 1], idx[i + 1, j + 1, k + 1],
                              idx[i, j + 1, k + 1]])
        conns.append(np.array(c))
    return np.vstack(nodes), conns, grids, (nx, ny, nz)


def write_deck(path, n, z0, cut, penalty):
    x, conns, grids, (nx, ny, nz) = parts(n, z0)
    lower, upper = conns
    if not cut:
        # The whole block: the upper part's nodes on the cut replaced by the lower part's.
        remap = np.arange(len(x))
        remap[grids[1][:, :, 0].ravel()] = grids[0][:, :, nz].ravel()
        upper = remap[upper]
    used = np.unique(np.concatenate([lower.ravel(), upper.ravel()]))
    # Element numbers: the lower part's from 1, the upper part's after; in each part the
    # element of grid cell (i, j, k) is i*ny*nz + j*nz + k.
    cell = lambda i, j, k: i * ny * nz + j * nz + k  # noqa: E731
    ne = len(lower)
    tol = 1e-9
    with open(path, "w") as f:
        w = f.write
        w("** The block cut at 30 degrees: CalculiX reference for pdcontact\n*NODE, NSET=NALL\n")
        for i in used:
            w(f"{i + 1}, " + ", ".join(f"{v:.12e}" for v in x[i]) + "\n")
        w("*ELEMENT, TYPE=C3D8I, ELSET=EALL\n")
        for e, c in enumerate(np.vstack([lower, upper])):
            w(f"{e + 1}, " + ", ".join(str(v + 1) for v in c) + "\n")

        def nset(name, ids):
            deck._nset(f, name, sorted(set(int(i) for i in ids)))

        nset("NSYMY", [i for i in used if abs(x[i, 1]) < tol])
        nset("NBOTTOM", [i for i in used if abs(x[i, 2]) < tol])
        nset("NTOP", [i for i in used if abs(x[i, 2] - 1.0) < tol])
        nset("NLOWER", grids[0][:, :, nz].ravel())
        if cut:
            nset("NUPPER", grids[1][:, :, 0].ravel())
            # Faces: the lower part's top layer, its face S2 (nodes 5-8); the upper part's
            # bottom layer, its face S1 (nodes 1-4).
            w("*SURFACE, NAME=SLOWER\n")
            for i in range(nx):
                for j in range(ny):
                    w(f"{cell(i, j, nz - 1) + 1}, S2\n")
            w("*SURFACE, NAME=SUPPER\n")
            for i in range(nx):
                for j in range(ny):
                    w(f"{ne + cell(i, j, 0) + 1}, S1\n")
        w("*MATERIAL, NAME=ELASTIC\n*ELASTIC\n")
        w(f"{E:.10g}, {NU:.10g}\n*DENSITY\n1000.\n")
        w("*SOLID SECTION, ELSET=EALL, MATERIAL=ELASTIC\n")
        w("*BOUNDARY\nNSYMY, 2, 2\nNBOTTOM, 1, 1\nNBOTTOM, 3, 3\nNTOP, 1, 1\n")
        if cut:
            w("*SURFACE INTERACTION, NAME=SI\n")
            w(f"*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n{penalty:.6g}\n")
            w("*CONTACT PAIR, INTERACTION=SI, TYPE=SURFACE TO SURFACE\nSUPPER, SLOWER\n")
        # The load step, then two more at the same load: CalculiX matches the faces once
        # at the start of an increment; the extra steps match them in the loaded state.
        steps = 3 if cut else 1
        for s in range(steps):
            w("*STEP, INC=200\n*STATIC\n1., 1.\n")
            if s == 0:
                w("*DLOAD\n")
                for i in range(nx):
                    for j in range(ny):
                        w(f"{ne + cell(i, j, nz - 1) + 1}, P2, {STRESS:.10g}\n")
            if s == steps - 1:
                w("*NODE PRINT, NSET=NTOP\nU\n*NODE PRINT, NSET=NLOWER\nU\n")
                if cut:
                    w("*NODE PRINT, NSET=NUPPER\nU\n")
                w("*NODE PRINT, NSET=NBOTTOM, TOTALS=ONLY\nRF\n")
            w("*END STEP\n")
    return x


def interior(p):
    return (np.abs(p[:, 0]) < 0.4) & (p[:, 1] < 0.4)


def fe_case(n, z0, cut, workdir, penalty):
    job = f"{'cut' if cut else 'whole'}_{n}"
    x = write_deck(os.path.join(workdir, job + ".inp"), n, z0, cut, penalty)
    seconds = ccx.run(job, workdir)
    dat = ccx.read_dat(os.path.join(workdir, job + ".dat"))
    top = dat[("displacements", "NTOP")]
    out = {"top": float(np.mean([u[2] for u in top.values()])), "seconds": seconds}
    out["reaction"] = dat[("total force", "NBOTTOM")][0][2]
    if cut:
        def face(name):
            d = dat[("displacements", name)]
            ids = np.array(sorted(d))
            u = np.array([d[i] for i in ids])
            return x[ids], u
        (pl, ul), (pu, uu) = face("NLOWER"), face("NUPPER")
        # Nodes coincide pairwise: the slide at each node, over the interior.
        order_l = np.lexsort((pl[:, 1], pl[:, 0]))
        order_u = np.lexsort((pu[:, 1], pu[:, 0]))
        assert np.allclose(pl[order_l], pu[order_u])
        rel = uu[order_u] - ul[order_l]
        keep = interior(pl[order_l])
        out["slide"] = float(np.mean(rel[keep] @ ALONG))
    return out


def pd_case(path):
    """pdcontact's figures from the JSON `pdcontact fracture --case closing --json` printed."""
    d = json.load(open(path))
    return {"top": d["inclined_displacement"], "whole": d["inclined_whole_displacement"],
            "slide": d["inclined_slide"], "particles": d["inclined_particles"], "spacing": d["spacing"],
            "iterations": d["inclined_iterations"], "seconds": d["inclined_seconds"]}


def last_frame(folder):
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy
    frames = sorted(glob.glob(os.path.join(folder, "frame_*", "*_particles.vtu")))
    if not frames:
        raise SystemExit(f"{folder}: no frame_*/*_particles.vtu (`pdcontact run SCENE -o {folder}`)")
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(frames[-1])
    r.Update()
    g = r.GetOutput()
    data = {"x": vtk_to_numpy(g.GetPoints().GetData()).astype(float)}
    for name in ("displacement", "volume"):
        data[name] = vtk_to_numpy(g.GetPointData().GetArray(name)).astype(float)
    return data


def slide_at_cut(x, u, z0, spacing):
    """The jump across the cut of the displacement along it, at the cut: on each side, over
    the particles within two spacings of it away from the block's sides, the displacement
    along the cut fitted as a line in the distance from it and taken at distance nil (as
    pdcontact's `inclined_slide`)."""
    d = (x - np.array([0.0, 0.0, z0])) @ np.array([math.sin(TILT), 0.0, math.cos(TILT)])
    along = u @ ALONG
    at = []
    for sign in (1.0, -1.0):
        m = interior(x) & (sign * d > 0) & (sign * d < 2.0 * spacing)
        a = np.vstack([np.ones(m.sum()), d[m]]).T
        at.append(np.linalg.lstsq(a, along[m], rcond=None)[0][0])
    return float(at[0] - at[1])


def pd_frames(cut, whole, z0):
    """pdcontact's figures from the last frames of a run of the cut block and of the whole
    one (`tools/gmsh_inclined_block.py`): the top's mean displacement along z, and the slide
    at the cut; the spacing is the lattice spacing of the particles' median volume."""
    c, w = last_frame(cut), last_frame(whole)
    top = lambda d: float(d["displacement"][np.abs(d["x"][:, 2] - 1.0) < 1e-9, 2].mean())  # noqa: E731
    spacing = float(np.median(c["volume"]) ** (1.0 / 3.0))
    slide = slide_at_cut(c["x"], c["displacement"], z0, spacing)
    return {"top": top(c), "whole": top(w), "slide": slide, "particles": len(c["x"]),
            "spacing": None, "label": cut, "delta": spacing}


def main():
    global NU
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("pd", nargs="*", help="what `pdcontact fracture --case closing --json` printed")
    ap.add_argument("--frames", nargs=2, metavar=("CUT", "WHOLE"),
                    help="instead: the output folders of `pdcontact run` on the scenes of "
                         "tools/gmsh_inclined_block.py (the cut block, the whole one)")
    ap.add_argument("--z0", type=float, default=0.5125, help="with --frames: the cut's height at x = 0")
    ap.add_argument("--n", type=int, nargs="+", default=[20, 40],
                    help="elements along x (half as many along y and along z in each part)")
    ap.add_argument("--penalty", type=float, default=1e13, help="contact penalty, Pa/m")
    ap.add_argument("--workdir", help="keep CalculiX's files here")
    ap.add_argument("--nu", type=float, default=NU, help="Poisson's ratio (the PD runs' own)")
    args = ap.parse_args()
    NU = args.nu
    if args.frames:
        pds = [pd_frames(*args.frames, args.z0)]
        z0 = args.z0
    elif args.pd:
        pds = [pd_case(p) for p in args.pd]
        # The cut's height at x = 0, as the PD runs place it (between particle rows there).
        z0s = {round((round(0.5 / p["spacing"]) + 0.25) * p["spacing"], 12) for p in pds}
        if len(z0s) != 1:
            raise SystemExit(f"the runs cut the block at different heights {sorted(z0s)}: "
                             "compare runs whose spacing puts the cut at the same height")
        z0 = z0s.pop()
    else:
        raise SystemExit("give the study's JSON or --frames CUT WHOLE")
    workdir = args.workdir or tempfile.mkdtemp(prefix="fe_inclined_")
    os.makedirs(workdir, exist_ok=True)
    rows = []
    try:
        for n in args.n:
            fw = fe_case(n, z0, False, workdir, args.penalty)
            fc = fe_case(n, z0, True, workdir, args.penalty)
            rows.append((n, fw, fc))
    finally:
        if not args.workdir:
            shutil.rmtree(workdir, ignore_errors=True)
    mm = 1e3
    print(f"cut at z0 = {z0} m (x = 0), 30 degrees, nu = {NU}; lengths in mm")
    print("| model | top, whole | top, cut | cut less whole | slide along the cut | wall |")
    print("|---|---:|---:|---:|---:|---:|")
    for n, fw, fc in rows:
        print(f"| CalculiX C3D8I, {n} x {n // 2} x 2*{n // 2} | {fw['top'] * mm:.4f} | {fc['top'] * mm:.4f} | "
              f"{(fc['top'] - fw['top']) * mm:.4f} | {fc['slide'] * mm:.4f} | "
              f"{fw['seconds']:.1f} s + {fc['seconds']:.1f} s |")
    for p in pds:
        what = (f"spacing {p['spacing']} m" if p["spacing"] else
                f"{p['label']}, Δ = {p['delta']:.4f} m")
        wall = f"{p['seconds']:.1f} s ({p['iterations']} ADR iterations, cut)" if "seconds" in p else ""
        print(f"| pdcontact, {what} ({p['particles']} particles) | {p['whole'] * mm:.4f} | "
              f"{p['top'] * mm:.4f} | {(p['top'] - p['whole']) * mm:.4f} | {p['slide'] * mm:.4f} | "
              f"{wall} |")
    for n, fw, fc in rows:
        print(f"reactions at the bottom (n = {n}): whole {fw['reaction']:.6g} N, cut {fc['reaction']:.6g} N "
              f"(load {STRESS * 0.5:.6g} N)")


if __name__ == "__main__":
    main()
