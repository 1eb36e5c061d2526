"""A sphere pressed into a deformable block of the same material: the CalculiX C3D10 reference.

    PYTHONPATH=tools python3 -m fe_reference.block L [--d D] [--h H] [--fine F] [--hmax HS]
        [--block-hmax HB] [--growth G] [--a A] [--penalty K] [--sphere-youngs E1]
        [--rematch N] [--threads N] [--workdir DIR [--reuse]] [--json PATH] [--profiles]

The geometry of tools/gmsh_sphere_block.py (issue 40: how large must a block be to stand for
a half-space): quarter models, symmetry planes x = 0 and y = 0 on both bodies; the upper body
the quarter x, y >= 0 of the sphere R = 1 m centred at (0, 0, R); the lower the quarter block
0 <= x, y <= L/2, -D <= z <= 0 (D = L unless given), held u_z = 0 on its bottom z = -D (the
symmetry plane pdcontact's scene puts there: a frictionless support). E = 1 GPa, nu = 0.25,
small strain, both bodies (`--sphere-youngs 1e12`: the sphere 1,000 times stiffer, a rigid
ball pressed into the block, E* = E/(1 - nu^2) to 0.1 %; the sphere's own figures then mean
little, its strains a thousandth of the block's). Load: a uniform body force on the sphere
totalling P/4 (*DLOAD GRAV), P such that Hertz's contact radius for the sphere on a
half-space is a = A (METHOD.md section 7: R* = R, 1/E* = (1 - nu^2)(1/E_sphere + 1/E));
nothing but the contact holds the sphere along z. C3D10 on both, graded toward the contact point (0, 0, 0) as the sphere
reference grades its mesh (mesh.quarter; size H within F of the point, slope G beyond, up to
HS on the sphere and HB in the block). Contact: `*CONTACT PAIR, TYPE=SURFACE TO SURFACE`,
the sphere's cap r < 2a the slave, the block's top faces within 3a of the axis the master,
linear pressure-overclosure K = 1e14 Pa/m, frictionless, two re-matching steps (as the sphere
reference, docs/FE_REFERENCE.md). The sphere starts a^2/(2R) into the block, so that the
first iteration has contact.

Figures, on each body, as the sphere reference computes them: the normal contact force of each
surface node is the internal force of the elements around it (less the body force on the
sphere), its pressure that force over the node's tributary area (undeformed; the corner nodes
of the 6-node faces have none and give no sample), the MRE over the samples within 0.8a, the
fitted contact radius, the largest sample against p0 (the "peak"), and the force balance.
"""
import argparse
import json
import math
import os
import tempfile
import time
from dataclasses import dataclass

import numpy as np
import gmsh

from . import ccx, deck, forces, metrics, surface
from .mesh import TET10_EDGES, _midside_order, _nodes_and, _size_field, _vertex_at, quarter
from .problem import Problem


@dataclass(frozen=True)
class SphereOnBlock(Problem):
    """Hertz for a sphere on a half-space: E* = E / (2 (1 - nu^2)) of the same material, or
    1/E* = (1 - nu^2)(1/E_sphere + 1/E) where the sphere's modulus is given."""

    sphere_youngs: float = 0.0   # the sphere's E, Pa (0: the block's)

    @property
    def youngs_sphere(self) -> float:
        return self.sphere_youngs if self.sphere_youngs > 0.0 else self.youngs

    @property
    def e_star(self) -> float:
        return 1.0 / ((1.0 - self.poisson ** 2) * (1.0 / self.youngs_sphere + 1.0 / self.youngs))


def block_mesh(half, depth, h, hmax, fine, growth):
    """C3D10 quarter block [0, half]^2 x [-depth, 0], graded toward the corner at the origin."""
    gmsh.initialize(["-nt", "1"])
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("block")
        gmsh.model.occ.addBox(0, 0, -depth, half, half, depth)
        gmsh.model.occ.synchronize()
        _size_field(_vertex_at((0.0, 0.0, 0.0)), h, hmax, fine, growth)
        gmsh.option.setNumber("Mesh.Algorithm", 6)
        gmsh.option.setNumber("Mesh.Algorithm3D", 1)
        gmsh.option.setNumber("Mesh.Optimize", 1)
        gmsh.option.setNumber("Mesh.SecondOrderIncomplete", 0)
        gmsh.model.mesh.generate(3)
        gmsh.model.mesh.setOrder(2)
        x, conn = _nodes_and(3, 11, 10)
    finally:
        gmsh.finalize()
    for k in range(3):
        x[np.abs(x[:, k]) < 1e-12, k] = 0.0
    x[np.abs(x[:, 2] + depth) < 1e-12, 2] = -depth
    return x, _midside_order(x, conn, 4, TET10_EDGES)


def plane_faces(x, conn, z, reach):
    """[(element, face label, node ids)] of C3D10 faces on the plane z with every node within
    `reach` of the z axis in x and y."""
    on = (np.abs(x[:, 2] - z) < 1e-9) & (np.abs(x[:, 0]) <= reach) & (np.abs(x[:, 1]) <= reach)
    out = []
    for label, local in surface.C3D10_FACES:
        ids = conn[:, local]
        for e in np.nonzero(on[ids].all(axis=1))[0]:
            out.append((int(e), label, ids[e]))
    return out


def write_deck(path, xs, cs, xb, cb, sfaces, bfaces, problem, depth, *, penalty, rematch,
               patch_s, patch_b, solver):
    ns = len(xs)
    weight = problem.load * 0.25 / forces.volume(xs, cs)
    tol = 1e-9
    x = np.vstack([xs, xb])
    with open(path, "w") as f:
        w = f.write
        w("** Sphere pressed into a deformable block: CalculiX reference (tools/fe_reference/block.py)\n")
        w("*NODE, NSET=NALL\n")
        for i, p in enumerate(x):
            w(f"{i + 1}, " + ", ".join(f"{v:.12e}" for v in p) + "\n")
        w("*ELEMENT, TYPE=C3D10, ELSET=SPHERE\n")
        for e, c in enumerate(cs):
            w(f"{e + 1}, " + ", ".join(str(v + 1) for v in c) + "\n")
        w("*ELEMENT, TYPE=C3D10, ELSET=BLOCK\n")
        for e, c in enumerate(cb):
            w(f"{len(cs) + e + 1}, " + ", ".join(str(v + ns + 1) for v in c) + "\n")
        deck._nset(f, "NPATCH", np.concatenate([patch_s, patch_b + ns]))
        deck._nset(f, "NBOTTOM", ns + np.nonzero(np.abs(xb[:, 2] + depth) < tol)[0])
        deck._nset(f, "NSYMX", np.nonzero(np.abs(x[:, 0]) < tol)[0])
        deck._nset(f, "NSYMY", np.nonzero(np.abs(x[:, 1]) < tol)[0])
        deck._nset(f, "NREF", [int(np.argmin(np.linalg.norm(xs, axis=1)))])
        w("*SURFACE, NAME=SSPHERE\n")
        for e, label, _ in sfaces:
            w(f"{e + 1}, S{label}\n")
        w("*SURFACE, NAME=SBLOCK\n")
        for e, label, _ in bfaces:
            w(f"{len(cs) + e + 1}, S{label}\n")
        w("*MATERIAL, NAME=ELASTIC\n*ELASTIC\n")
        w(f"{problem.youngs:.10g}, {problem.poisson:.10g}\n*DENSITY\n1.\n")
        w("*MATERIAL, NAME=SPHEREMAT\n*ELASTIC\n")
        w(f"{problem.youngs_sphere:.10g}, {problem.poisson:.10g}\n*DENSITY\n1.\n")
        w("*SOLID SECTION, ELSET=SPHERE, MATERIAL=SPHEREMAT\n")
        w("*SOLID SECTION, ELSET=BLOCK, MATERIAL=ELASTIC\n")
        w("*BOUNDARY\nNSYMX, 1, 1\nNSYMY, 2, 2\nNBOTTOM, 3, 3\n")
        w("*SURFACE INTERACTION, NAME=SI\n*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n")
        w(f"{penalty:.6g}\n")
        w("*CONTACT PAIR, INTERACTION=SI, TYPE=SURFACE TO SURFACE\nSSPHERE, SBLOCK\n")
        solver_opt = f", SOLVER={solver}" if solver else ""
        for k in range(1 + rematch):
            w(f"*STEP, INC=200\n*STATIC{solver_opt}\n1., 1.\n")
            if k == 0:
                w(f"*DLOAD\nSPHERE, GRAV, {weight:.12g}, 0., 0., -1.\n")
            w("*NODE PRINT, NSET=NREF\nU\n")
            if k == rematch:
                w("*NODE PRINT, NSET=NPATCH\nU\n")
                w("*NODE PRINT, NSET=NBOTTOM, TOTALS=ONLY\nRF\n")
            w("*END STEP\n")
    return weight


def body_figures(x, conn, patch, disp, faces, problem, share, sign, weight=None, youngs=None):
    """Contact pressures on the faces' nodes from the internal forces of the elements around
    them; returns the figures and the (r, p) samples."""
    inpatch = np.zeros(len(x), dtype=bool)
    inpatch[patch] = True
    elements = conn[inpatch[conn].all(axis=1)]
    u = np.zeros_like(x)
    u[patch] = disp
    f = forces.internal_forces(x, elements, u, youngs or problem.youngs, problem.poisson)
    nodes, area, _, touching = surface.face_matrices(x, faces)
    force = sign * f[nodes, 2]
    if weight is not None:
        force = force + weight * forces.nodal_volumes(x, elements)[nodes]
    p = surface.pressures(force, area, None, "lumped")
    r = np.hypot(x[nodes, 0], x[nodes, 1])
    # Samples within 2a of the axis on both bodies, as the sphere reference's cap r < 2a:
    # the fit scans a' from half to twice the largest loaded radius, and the block's faces
    # reach 3a (to the corner 4.2a), where nodes carry round-off forces of either sign.
    sample = (area > 1e-3 * touching) & (r <= 2.0 * problem.contact_radius)
    res = metrics.accuracy(r[sample], p[sample], force.sum() / share, problem)
    res["peak_error"] = float(np.nanmax(p[sample]) / problem.p0 - 1.0)
    res["balance"] = float(force.sum() / share / problem.load - 1.0)
    return res, (r[sample], p[sample])


def run_block(l, d, h, fine, hmax_sphere, hmax_block, growth, problem, workdir, *,
              penalty=1e14, rematch=2, threads=1, solver="ITERATIVE CHOLESKY", reuse=False):
    t0 = time.perf_counter()
    a, radius = problem.contact_radius, problem.radius
    xs, cs = quarter(h, radius, hmax=hmax_sphere, fine=fine, growth=growth, full=True)
    slave_cap = 2.0 * a
    sfaces = surface.sphere_faces(xs, cs, surface.C3D10_FACES, radius,
                                  -math.sqrt(radius ** 2 - slave_cap ** 2))
    overlap = 0.5 * problem.approach
    xs = xs + np.array([0.0, 0.0, radius - overlap])     # the pole a^2/(2R) into the block
    xb, cb = block_mesh(0.5 * l, d, h, hmax_block, fine, growth)
    bfaces = plane_faces(xb, cb, 0.0, 3.0 * a)
    patch_s = deck.patch_nodes(cs, np.unique(np.concatenate([q[2] for q in sfaces])))
    patch_b = deck.patch_nodes(cb, np.unique(np.concatenate([q[2] for q in bfaces])))
    t_mesh = time.perf_counter() - t0
    os.makedirs(workdir, exist_ok=True)
    weight = write_deck(os.path.join(workdir, "contact.inp"), xs, cs, xb, cb, sfaces, bfaces,
                        problem, d, penalty=penalty, rematch=rematch, patch_s=patch_s,
                        patch_b=patch_b, solver=solver)
    if reuse and os.path.exists(os.path.join(workdir, "contact.dat")):
        t_ccx = float("nan")          # read the results of an earlier run of the same case
    else:
        t_ccx = ccx.run("contact", workdir, threads)
    dat = ccx.read_dat(os.path.join(workdir, "contact.dat"))
    iters = ccx.log_iterations(os.path.join(workdir, "contact.log"))
    disp = dat[("displacements", "NPATCH")]
    ns = len(xs)
    us = np.array([disp[int(i)] for i in patch_s])
    ub = np.array([disp[int(i) + ns] for i in patch_b])
    bottom = dat[("total force", "NBOTTOM")][0][2]
    upper, prof_u = body_figures(xs, cs, patch_s, us, sfaces, problem, 0.25, 1.0, weight,
                                 problem.youngs_sphere)
    lower, prof_l = body_figures(xb, cb, patch_b, ub, bfaces, problem, 0.25, -1.0)
    return dict(l=l, d=d, h=h, h_over_a=h / a, fine=fine, hmax_sphere=hmax_sphere,
                hmax_block=hmax_block, growth=growth,
                nodes=int(len(xs) + len(xb)), nodes_sphere=int(len(xs)), nodes_block=int(len(xb)),
                elements=int(len(cs) + len(cb)), elements_sphere=int(len(cs)),
                elements_block=int(len(cb)), iterations=iters, upper=upper, lower=lower,
                support_reaction_error=float(abs(bottom) * 4 / problem.load - 1.0),
                mesh_seconds=t_mesh, ccx_seconds=t_ccx, wall_seconds=time.perf_counter() - t0,
                profiles={"upper": prof_u, "lower": prof_l})


def main():
    ap = argparse.ArgumentParser(prog="python3 -m fe_reference.block",
                                 description=__doc__.splitlines()[0])
    ap.add_argument("l", type=float, help="block width L (m); the quarter is L/2 wide")
    ap.add_argument("--d", type=float, default=None, help="block depth D (m, default L)")
    ap.add_argument("--h", type=float, default=0.03, help="element size at the contact (m)")
    ap.add_argument("--fine", type=float, default=0.4, help="size H within this distance (m)")
    ap.add_argument("--hmax", type=float, default=0.12, help="the sphere's largest size (m)")
    ap.add_argument("--block-hmax", type=float, default=0.4, help="the block's largest size (m)")
    ap.add_argument("--growth", type=float, default=0.3)
    ap.add_argument("--a", type=float, default=0.3, help="Hertz contact radius (m)")
    ap.add_argument("--penalty", type=float, default=1e14, help="contact stiffness, Pa/m")
    ap.add_argument("--sphere-youngs", type=float, default=0.0,
                    help="the sphere's Young's modulus (Pa; default the block's): 1e12 stands "
                    "for a rigid ball pressed into the block")
    ap.add_argument("--rematch", type=int, default=2)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--workdir", help="keep CalculiX's files here (default: a temporary one)")
    ap.add_argument("--json", metavar="PATH")
    ap.add_argument("--reuse", action="store_true", help="with --workdir: read the results "
                    "CalculiX left there for the same case instead of running it again")
    ap.add_argument("--profiles", action="store_true", help="also print p(r) on each body")
    o = ap.parse_args()
    problem = SphereOnBlock(contact_radius=o.a, sphere_youngs=o.sphere_youngs)
    d = o.d if o.d is not None else o.l
    tmp = None
    if o.workdir:
        wd = o.workdir
    else:
        tmp = tempfile.TemporaryDirectory(prefix="fe_block_")
        wd = tmp.name
    print(f"sphere R = {problem.radius:g} m on a block {o.l:g} x {o.l:g} x {d:g} m, E = "
          f"{problem.youngs:.3g} Pa, nu = {problem.poisson:g}; P = {problem.load:.6g} N for "
          f"a = {o.a:g} m, p0 = {problem.p0:.6g} Pa (half-space Hertz)", flush=True)
    res = run_block(o.l, d, o.h, o.fine, o.hmax, o.block_hmax, o.growth, problem, wd,
                    penalty=o.penalty, rematch=o.rematch, threads=o.threads, reuse=o.reuse)
    print(f"C3D10 h = {o.h:g} m: nodes {res['nodes_sphere']} + {res['nodes_block']}, elements "
          f"{res['elements_sphere']} + {res['elements_block']}, Newton iterations "
          f"{res['iterations']}, ccx {res['ccx_seconds']:.1f} s, total {res['wall_seconds']:.1f} s; "
          f"support reaction / load - 1 = {res['support_reaction_error']:.1e}")
    for body in ("upper", "lower"):
        f = res[body]
        print(f"  {body:<8} MRE {100 * f['mre']:.2f} % ({f['samples']} nodes within 0.8a), radius "
              f"{100 * f['radius_error']:+.2f} %, peak {100 * f['peak_error']:+.2f} %, contact "
              f"force / load - 1 = {f['balance']:.1e}")
        if o.profiles:
            r, p = res["profiles"][body]
            for k in np.argsort(r):
                print(f"    r/a {r[k] / o.a:.4f}  p/p0 {p[k] / problem.p0:.5f}  Hertz "
                      f"{problem.pressure(r[k]) / problem.p0:.5f}")
    if o.json:
        out = {k: v for k, v in res.items() if k != "profiles"}
        with open(o.json, "w") as fj:
            json.dump(out, fj, indent=1, default=float)
            fj.write("\n")
    if tmp is not None:
        tmp.cleanup()


if __name__ == "__main__":
    main()
