"""Quarter caps of the Hertz sphere on a rigid plane: the CalculiX C3D10 reference.

    PYTHONPATH=tools python3 -m fe_reference.caps SHAPE H [--w 2] [--fine 0.2] [--hmax 0.05]
        [--workdir DIR] [--threads N]

The continuum solution of the quarter-cap scenes of docs/VALIDATION.md, to tell what of a
PD figure is the body and what the model. SHAPE:
  sector      the demo's body, meshes/sphere_cap_quarter_shape.geo (the shell w a deep under
              a patch reaching w a to each side of the pole; --w, default 2), loaded on its
              inner spherical face "top";
  box         tools/gmsh_hertz_cap.py --shape box: the shell R - 3a <= r <= R cut by the box
              0 <= x, y <= 3a, z <= 0, loaded on its inner spherical face;
  hemisphere  a deep body for comparison: the quarter of the lower hemisphere, loaded on its
              equatorial face z = 0.
R = 1 m, E = 1 GPa, nu = 0.25, a quarter of P = 4.8e6 N (Hertz: a = 0.15 m), symmetry
planes x = 0 and y = 0, small strain. Quadratic tets (C3D10) of size H within --fine of the
pole, growing with slope 0.3 to --hmax. Load: a uniform -z traction on the load face as
consistent nodal forces (*CLOAD, total 1.2e6 N). Contact: face-to-face penalty, linear,
K = 1e14 Pa/m, against a fixed block standing in for the rigid plane, two re-matching steps
(as the sphere reference, docs/FE_REFERENCE.md). Pressure: the contact forces at the
surface nodes (internal forces of the elements around the contact) over each node's area,
"lumped" as pdcontact measures itself, and "consistent" (p = M^-1 F). Figures as
METHOD.md section 7, plus the level: the sum of p over the sum of Hertz's p within 0.8a.
"""
import argparse
import json
import math
import os
import tempfile
import time

import numpy as np
import gmsh

from . import ccx, deck, forces, metrics, surface
from .mesh import TET10_EDGES, _midside_order, _size_field
from .problem import Problem

MESHES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "meshes")
PB = Problem()          # R = 1, E = 1e9, nu = 0.25, a = 0.15 -> P = 4.8e6
A = PB.contact_radius
FQ = PB.load / 4        # quarter load 1.2e6 N


def build(shape):
    """Builds the body in the current gmsh model; returns the load face's surface tags."""
    if shape == "sector":
        gmsh.open(os.path.join(MESHES, "sphere_cap_quarter_shape.geo"))
        groups = {gmsh.model.getPhysicalName(d, t): (d, t) for d, t in gmsh.model.getPhysicalGroups()}
        return list(gmsh.model.getEntitiesForPhysicalGroup(*groups["top"]))
    occ = gmsh.model.occ
    if shape == "box":
        # As tools/gmsh_hertz_cap.py --shape box. (The same spheres, rotated so that OCC's parametric
        # pole is not at the contact point: identical geometry, regular surface mesh there.)
        outer = occ.addSphere(0, 0, 0, 1.0)
        inner = occ.addSphere(0, 0, 0, 1.0 - 3 * A)
        occ.rotate([(3, outer), (3, inner)], 0, 0, 0, 1.0, 1.0, 0.0, 0.5 * math.pi)
        shell, _ = occ.cut([(3, outer)], [(3, inner)])
        box = occ.addBox(0, 0, -1.1, 3 * A, 3 * A, 1.1)
        occ.intersect(shell, [(3, box)])
        occ.synchronize()
        vols = [(3, t) for _, t in gmsh.model.getEntities(3)]
        faces = [t for _, t in gmsh.model.getBoundary(vols, oriented=False)]

        def centre_radius(tag):
            x, y, z = occ.getCenterOfMass(2, tag)
            return (x * x + y * y + z * z) ** 0.5
        spheres = [t for t in faces if "Sphere" in gmsh.model.getType(2, t)]
        return [min(spheres, key=centre_radius)]
    if shape == "hemisphere":
        ball = occ.addSphere(0, 0, 0, 1.0)
        occ.rotate([(3, ball)], 0, 0, 0, 1.0, 1.0, 0.0, 0.5 * math.pi)
        box = occ.addBox(0, 0, -2.0, 2.0, 2.0, 2.0)
        occ.intersect([(3, ball)], [(3, box)])
        occ.synchronize()
        faces = gmsh.model.getEntitiesInBoundingBox(-0.1, -0.1, -1e-6, 1.1, 1.1, 1e-6, 2)
        return [t for _, t in faces]
    raise ValueError(shape)


def make_mesh(shape, h, hmax, fine, w):
    # The .geo's parameters (a, R, w) come first, as -setnumber does on gmsh's command line.
    gmsh.initialize(["gmsh", "-nt", "1", "-setnumber", "a", repr(A), "-setnumber", "R", "1",
                     "-setnumber", "w", repr(w)])
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add(shape)
        top = build(shape)
        _size_field(None, h, hmax, fine, 0.3, centre=(0.0, 0.0, -1.0))
        gmsh.option.setNumber("Mesh.Algorithm", 6)
        gmsh.option.setNumber("Mesh.Algorithm3D", 1)
        gmsh.option.setNumber("Mesh.Optimize", 1)
        gmsh.option.setNumber("Mesh.SecondOrderIncomplete", 0)
        gmsh.model.mesh.generate(3)
        gmsh.model.mesh.setOrder(2)
        if shape == "box":
            # a few curved slivers at the inner-sphere / box-side edge invert: untangle
            gmsh.option.setNumber("Mesh.HighOrderOptimize", 2)
            gmsh.model.mesh.optimize("HighOrderElastic")
        tags, coords, _ = gmsh.model.mesh.getNodes()
        x = coords.reshape(-1, 3)
        index = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
        index[tags] = np.arange(len(tags))
        types, _, enodes = gmsh.model.mesh.getElements(3)
        assert list(types) == [11], types
        conn = index[np.asarray(enodes[0], dtype=np.int64).reshape(-1, 10)]
        tris = []
        for s in top:
            ty, _, en = gmsh.model.mesh.getElements(2, s)
            assert list(ty) == [9], ty
            tris.append(index[np.asarray(en[0], dtype=np.int64).reshape(-1, 6)])
        tris = np.vstack(tris)
    finally:
        gmsh.finalize()
    used = np.unique(conn)
    renum = np.full(len(x), -1, dtype=np.int64)
    renum[used] = np.arange(len(used))
    x, conn, tris = x[used].copy(), renum[conn], renum[tris]
    assert (tris >= 0).all()
    for k in range(3):
        x[np.abs(x[:, k]) < 1e-12, k] = 0.0
    # gmsh tet10 -> Abaqus/CalculiX order: swap the last two midside nodes (edges 2-3, 1-3)
    gconn = conn[:, [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]]
    if shape != "box":   # straight-sided interior: check the permutation geometrically
        assert (gconn == _midside_order(x, conn, 4, TET10_EDGES)).all()
    conn = gconn
    # Snap the nodes of the outer sphere exactly onto it (gmsh places them to ~1e-9..1e-7).
    rad = np.linalg.norm(x, axis=1)
    on = np.abs(rad - 1.0) < 1e-5
    dev = float(np.abs(rad[on] - 1.0).max())
    x[on] /= rad[on][:, None]
    return x, conn, tris, dev


def tri_load(x, tris, total):
    """Consistent nodal z-forces of a uniform -z traction totalling ``total`` on the faces."""
    faces = [(0, 0, t) for t in tris]
    nodes, area, _, _ = surface.face_matrices(x, faces)
    return nodes, -total * area / area.sum(), float(area.sum())


def level(r, p):
    inside = r <= 0.8 * A
    theory = PB.p0 * np.sqrt(np.clip(1 - (r[inside] / A) ** 2, 0, None))
    return float(p[inside].sum() / theory.sum())


def main():
    ap = argparse.ArgumentParser(prog="python3 -m fe_reference.caps",
                                 description=__doc__.splitlines()[0])
    ap.add_argument("shape", choices=["sector", "box", "hemisphere"])
    ap.add_argument("h", type=float, help="element size near the contact (m)")
    ap.add_argument("--w", type=float, default=2.0, help="sector: depth and reach in a")
    ap.add_argument("--fine", type=float, default=0.2)
    ap.add_argument("--hmax", type=float, default=0.05)
    ap.add_argument("--workdir", help="keep CalculiX's files here (default: a temporary one)")
    ap.add_argument("--threads", type=int, default=2)
    args = ap.parse_args()
    t0 = time.perf_counter()
    tmp = None
    if args.workdir:
        wd = args.workdir
        os.makedirs(wd, exist_ok=True)
    else:
        tmp = tempfile.TemporaryDirectory(prefix="fe_caps_")
        wd = tmp.name
    x, conn, tris, dev = make_mesh(args.shape, args.h, args.hmax, args.fine, args.w)
    load_nodes, load_f, top_area = tri_load(x, tris, FQ)
    slave_cap = 2 * A
    zcut = -math.sqrt(1 - slave_cap ** 2)
    faces = surface.sphere_faces(x, conn, surface.C3D10_FACES, 1.0, zcut)
    nodes, area, mmat, touching = surface.face_matrices(x, faces)
    patch = deck.patch_nodes(conn, nodes)
    assert not np.isin(load_nodes, patch).any(), "load face touches the contact patch"
    g = deck.graded(-args.h, 2.0 * A, 1.5 * slave_cap, args.h)
    pl = deck.plane_block(g, 1.0, 0.05)
    plane = (pl[0], pl[1], "C3D8", pl[2])
    t_mesh = time.perf_counter() - t0
    deck.write_contact_deck(os.path.join(wd, "contact.inp"), x, conn, "C3D10", faces, PB,
                            penalty=1e14, overlap=0.5 * PB.approach, solver="ITERATIVE CHOLESKY",
                            plane=plane, patch_nodes=patch, surface_nodes=nodes, load_share=0.25,
                            loading="nodal", nodal_forces=(load_nodes, load_f))
    t_ccx = ccx.run("contact", wd, args.threads)
    dat = ccx.read_dat(os.path.join(wd, "contact.dat"))
    iters = ccx.log_iterations(os.path.join(wd, "contact.log"))
    disp = dat[("displacements", "NPATCH")]
    plane_rz = dat[("total force", "NPLANE")][0][2]
    inpatch = np.zeros(len(x), bool)
    inpatch[patch] = True
    elements = conn[inpatch[conn].all(axis=1)]
    u = np.zeros_like(x)
    for i in patch:
        u[i] = disp[int(i)]
    fint = forces.internal_forces(x, elements, u, PB.youngs, PB.poisson)
    fz = fint[nodes, 2]
    r = np.linalg.norm(x[nodes, :2], axis=1)
    sample = area > 1e-3 * touching
    out = dict(shape=args.shape, w=args.w if args.shape == "sector" else None, h=args.h, h_over_a=args.h / A, fine=args.fine, hmax=args.hmax,
               nodes=int(len(x)), elements=int(len(conn)), surface_nodes=int(len(nodes)),
               samples=int(sample.sum()), load_face_area=top_area, sphere_snap_dev=dev,
               iterations=iters)
    for method in ("lumped", "consistent"):
        p = surface.pressures(fz, area, mmat, method)
        rs, ps = (r[sample], p[sample]) if method == "lumped" else (r, p)
        m, n08 = metrics.mre(rs, ps, PB)
        fa, fp = metrics.fit_elliptic(rs, ps)
        out[method] = dict(level=level(rs, ps), mre=m, n_r08=n08, fit_A=fa, fit_p0=fp,
                           radius_error=fa / A - 1, fit_p0_ratio=fp / PB.p0)
    out["contact_force_sum"] = float(fz.sum())
    out["force_balance_error"] = float(fz.sum() / FQ - 1)
    out["plane_reaction"] = float(plane_rz)
    out["plane_reaction_error"] = float(abs(plane_rz) / FQ - 1)
    out["ccx_seconds"] = t_ccx
    out["mesh_seconds"] = t_mesh
    out["wall_seconds"] = time.perf_counter() - t0
    for method in ("lumped", "consistent"):
        o = out[method]
        print(f"{args.shape} h = {args.h:g} m ({len(conn)} C3D10), {method}: level {o['level']:.4f}, "
              f"MRE {100 * o['mre']:.3f} %, radius {100 * o['radius_error']:+.2f} %, "
              f"fitted p0 {100 * (o['fit_p0_ratio'] - 1):+.2f} %")
    print(json.dumps(out, indent=1))
    if tmp is not None:
        tmp.cleanup()


if __name__ == "__main__":
    main()
