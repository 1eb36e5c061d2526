"""One reference case: mesh, contact analysis, contact forces, the three figures."""
import os
import resource
import time

import numpy as np

from . import ccx, deck, forces, mesh, metrics, surface
from .problem import Problem

MODELS = {
    # name: (CalculiX element type, its faces, share of the sphere that is modelled)
    "cax8-axisymmetric": ("CAX8", surface.CAX8_FACES, 1.0),
    "c3d10-quarter": ("C3D10", surface.C3D10_FACES, 0.25),
}


def _children_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run_case(model, h_over_a, workdir, problem=Problem(), *, penalty=1e14, solver="auto",
             pressure="lumped", slave="auto", slave_cap=None, plane_fine=2.0, preload=0.5,
             rematch=2, nlgeom=False, loading="body", threads=2, mesh_options=None):
    """Runs one case in ``workdir``; returns a dict of figures, sizes and timings.

    h_over_a: element size at the contact over the Hertz radius a. penalty: slope of
    the linear pressure-overclosure law, Pa/m. pressure: "lumped" (p_i = F_i / A_i, the
    project's definition) or "consistent" (p = M^-1 F). slave: which surface is
    CalculiX's slave, "sphere" or "plane" ("auto": the plane for CAX8, see below).
    slave_cap: the sphere's contact surface is its cap r < slave_cap (default 2a). preload: the plane
    starts this fraction of a^2/R above the pole. rematch: extra load steps that redo
    CalculiX's slave/master matching in the loaded configuration. loading: "body" (the
    whole sphere under a uniform body force totalling P, as in the project's scene) or
    "equator" (the lower half, its equator a symmetry plane tied to a loaded reference
    node: the sphere squeezed between two planes).
    """
    t0 = time.perf_counter()
    etype, faces_def, share = MODELS[model]
    a, radius = problem.contact_radius, problem.radius
    h = h_over_a * a
    # The contact surface and the refined zone scale with the contact radius (the defaults
    # were set at a = 0.15 m: a cap of 0.3 m, refined to 0.22 m or 0.2 m from the pole).
    if slave_cap is None:
        slave_cap = 2.0 * a
    opts = dict(mesh_options or {})
    opts.setdefault("fine", (0.22 if model == "cax8-axisymmetric" else 0.2) * a / 0.15)
    if problem.ball > 0.0:
        # The rigid surface must lie on the ball: the strip reaches 1.5 slave caps from the
        # axis, the block's corner 1.5 sqrt(2) of them.
        reach = 1.5 if model == "cax8-axisymmetric" else 1.5 * np.sqrt(2.0)
        slave_cap = min(slave_cap, 0.98 * problem.ball / reach)
        if slave_cap <= 1.05 * a:
            raise ValueError(f"a ball of radius {problem.ball:g} m is too small for {model} at "
                             f"a = {a:g} m: the rigid surface would not cover the contact")
    if model == "cax8-axisymmetric":
        x, conn = mesh.axisymmetric(h, radius, full=loading == "body", **opts)
        plane = deck.plane_strip(deck.graded(1e-6 * radius, plane_fine * a, 1.5 * slave_cap, h),
                                 radius, 0.05 * radius)
        plane = (plane[0], plane[1], "CAX8", plane[2])
    else:
        x, conn = mesh.quarter(h, radius, full=loading == "body", **opts)
        plane = deck.plane_block(deck.graded(-h, plane_fine * a, 1.5 * slave_cap, h),
                                 radius, 0.05 * radius)
        plane = (plane[0], plane[1], "C3D8", plane[2])
    # A rigid ball in place of the plane: every node of the strip (block) dropped by the
    # ball's sag at its distance from the axis (all of them are held, so only the top
    # surface's shape matters).
    pnodes = plane[0].copy()
    pnodes[:, -1] -= problem.sag(np.linalg.norm(pnodes[:, :-1], axis=1))
    plane = (pnodes,) + plane[1:]
    if slave == "auto":
        # CalculiX's face-to-face contact skips slave faces of axisymmetric elements that
        # touch the axis (they expand into collapsed faces): there the plane is the slave.
        slave = "plane" if model == "cax8-axisymmetric" else "sphere"
    if solver == "auto":
        solver = "ITERATIVE CHOLESKY" if model == "c3d10-quarter" else None
    t_mesh = time.perf_counter() - t0

    zcut = -np.sqrt(radius ** 2 - slave_cap ** 2)
    faces = surface.sphere_faces(x, conn, faces_def, radius, zcut)
    nodes, area, m, touching = surface.face_matrices(x, faces)
    patch = deck.patch_nodes(conn, nodes)
    os.makedirs(workdir, exist_ok=True)
    job = "contact"
    centre = deck.write_contact_deck(
        os.path.join(workdir, job + ".inp"), x, conn, etype, faces, problem,
        penalty=penalty, overlap=preload * problem.approach, solver=solver, plane=plane,
        patch_nodes=patch, surface_nodes=nodes, load_share=share, slave=slave,
        nlgeom=nlgeom, rematch=rematch, loading=loading)
    cpu0 = _children_cpu()
    t_ccx = ccx.run(job, workdir, threads)
    cpu_ccx = _children_cpu() - cpu0
    iterations = ccx.log_iterations(os.path.join(workdir, job + ".log"))
    dat = ccx.read_dat(os.path.join(workdir, job + ".dat"))
    dim = x.shape[1]
    disp = dat[("displacements", "NPATCH")]
    reaction = dat[("total force", "NPLANE")][0][dim - 1]
    approach = -dat[("displacements", "NREF")][centre][dim - 1] + preload * problem.approach

    # Contact forces: the internal forces of the elements around the contact surface.
    inpatch = np.zeros(len(x), dtype=bool)
    inpatch[patch] = True
    elements = conn[inpatch[conn].all(axis=1)]
    u = np.zeros_like(x)
    for i in patch:
        u[i] = disp[int(i)][:dim]
    f = forces.internal_forces(x, elements, u, problem.youngs, problem.poisson, nlgeom)
    force = f[nodes, dim - 1]                   # normal (z) contact force of each node
    if loading == "body":
        # f_int = contact force + body force at a loaded node: take the body force off.
        weight = problem.load * share / forces.volume(x, conn)    # N/m^3, downward
        force = force + weight * forces.nodal_volumes(x, elements)[nodes]
    p = surface.pressures(force, area, m, pressure)
    r = np.linalg.norm(x[nodes, :dim - 1], axis=1)
    total = force.sum() / share
    # A node without tributary area carries no pressure sample (as in the project's
    # contact_patch): the axis node of the axisymmetric model (int N 2 pi r ds = 0) and
    # the corner nodes of 6-node triangles (int N dA = 0 on a flat face, ~1e-5 of the
    # face area on these curved ones).
    sample = area > 1e-3 * touching if pressure == "lumped" else np.ones(len(nodes), bool)
    result = metrics.accuracy(r[sample], p[sample], total, problem)
    # Cross-checks: the plane's reactions (CalculiX prints them for the 2-degree
    # expansion of an axisymmetric model), and the pressure of the sample nearest the
    # centre against Hertz there.
    plane_total = abs(reaction) * (180.0 if dim == 2 else 1.0 / share)
    k = np.argmin(np.where(sample, r, np.inf))
    result.update(
        model=model, h_over_a=h_over_a, nodes=int(len(x)), elements=int(len(conn)),
        surface_nodes=int(len(nodes)), iterations=iterations, pressure_method=pressure,
        slave=slave, loading=loading,
        plane_reaction_error=abs(plane_total - problem.load) / problem.load,
        centre_pressure_error=float(p[k] / problem.pressure(r[k]) - 1.0),
        centre_radius=float(r[k]),
        approach=approach, mesh_seconds=t_mesh, ccx_seconds=t_ccx, ccx_cpu_seconds=cpu_ccx,
        wall_seconds=time.perf_counter() - t0,
        profile={"r": r[sample], "p": p[sample]},
    )
    return result
