"""CalculiX input decks (Abaqus INP dialect) for the sphere on a rigid plane.

* The sphere: CAX8 (axisymmetric) or C3D10 (quarter, symmetry planes x = 0 and y = 0),
  linear elastic. Loaded either by a uniform body force totalling P over the whole
  sphere ("body", the project's scene: a load spread over the sphere by volume), or, as
  its lower half with the equator tied to a loaded centre node ("equator": exactly a
  sphere squeezed between two planes, the equator staying plane and free of shear).
* The rigid plane: a strip (CAX8) or block (C3D8) of elements under the pole, every node
  held fixed; its top faces are one contact surface, the sphere's cap r < slave_cap the
  other.
* Face-to-face ("SURFACE TO SURFACE") penalty contact, linear pressure-overclosure,
  frictionless. Small strain (no NLGEOM) unless asked; contact is still found in the
  displaced configuration, as CalculiX always does.
* Force control: P is applied in one step; the plane starts slightly above the pole so
  that contact (and with it a regular stiffness matrix) exists from the first iteration.
"""
import numpy as np

from . import forces


def _ids(f, values, per_line=12):
    values = [int(v) + 1 for v in values]
    for k in range(0, len(values), per_line):
        f.write(", ".join(str(v) for v in values[k:k + per_line]) + "\n")


def _nset(f, name, ids):
    f.write(f"*NSET, NSET={name}\n")
    _ids(f, ids)


def graded(x0, fine, width, h, growth=1.3):
    """Coordinates from x0: spacing h up to ``fine``, then growing by ``growth`` to width."""
    xs = [x0]
    step = h
    while xs[-1] < width - 1e-12:
        if xs[-1] >= fine:
            step *= growth
        xs.append(min(xs[-1] + step, width))
    return np.array(xs)


def plane_strip(r, radius, thickness):
    """CAX8 strip over the radii r, z in [-R - thickness, -R]: (nodes, conn, top face)."""
    nodes, conn = [], []

    def add(p):
        nodes.append(p)
        return len(nodes) - 1

    zt, zb = -radius, -radius - thickness
    zm = 0.5 * (zt + zb)
    for i in range(len(r) - 1):
        r0, r1 = r[i], r[i + 1]
        rm = 0.5 * (r0 + r1)
        conn.append([add((r0, zb)), add((r1, zb)), add((r1, zt)), add((r0, zt)),
                     add((rm, zb)), add((r1, zm)), add((rm, zt)), add((r0, zm))])
    return np.array(nodes), np.array(conn), 3


def plane_block(g, radius, thickness):
    """C3D8 block over the grid g x g, z in [-R - thickness, -R]: (nodes, conn, top face)."""
    n = len(g) - 1
    zt, zb = -radius, -radius - thickness
    idx = {}
    nodes = []
    for k, z in enumerate((zb, zt)):
        for j, y in enumerate(g):
            for i, xx in enumerate(g):
                idx[i, j, k] = len(nodes)
                nodes.append((xx, y, z))
    conn = []
    for j in range(n):
        for i in range(n):
            conn.append([idx[i, j, 0], idx[i + 1, j, 0], idx[i + 1, j + 1, 0], idx[i, j + 1, 0],
                         idx[i, j, 1], idx[i + 1, j, 1], idx[i + 1, j + 1, 1], idx[i, j + 1, 1]])
    return np.array(nodes), np.array(conn), 2


def write_contact_deck(path, x, conn, etype, faces, problem, *, penalty, overlap, solver,
                       plane, patch_nodes, surface_nodes, load_share, slave="sphere",
                       nlgeom=False, rematch=2, loading="body", nodal_forces=None):
    """Writes the contact analysis; returns the index of the node nearest the centre.

    loading: "body" (a uniform body force totalling P), "equator" (P at the centre node, the
    equator kept plane) or "nodal" (`nodal_forces` = (node indices, z forces), as they are).

    plane = (nodes, conn, element type, label of the top face). overlap: the plane starts
    this far (m) above the pole, so that contact exists from the first iteration (under
    force control the sphere floats: a different start only shifts the solution rigidly).
    """
    dim = x.shape[1]
    n = len(x)
    pnodes, pconn, ptype, ptop = plane
    pnodes = pnodes.copy()
    pnodes[:, -1] += overlap
    tol = 1e-9
    centre = int(np.argmin(np.linalg.norm(x, axis=1)))
    if loading == "body":
        equator = []
        weight = problem.load * load_share / forces.volume(x, conn)   # N/m^3
    elif loading == "nodal":
        equator = []
    elif loading == "equator":
        equator = np.nonzero(np.abs(x[:, -1]) < tol)[0]
        if np.linalg.norm(x[centre]) > tol:
            raise RuntimeError("no node at the sphere's centre")
    else:
        raise ValueError(loading)
    with open(path, "w") as f:
        w = f.write
        w("** Sphere on a rigid plane: CalculiX reference for pdcontact (tools/fe_reference)\n")
        # Numbers are written in at most 20 characters: CalculiX cuts longer fields
        # (a coordinate such as -3.872195057947475e-05 would silently become -3.87...).
        w("*NODE, NSET=NALL\n")
        for i, p in enumerate(np.vstack([x, pnodes])):
            w(f"{i + 1}, " + ", ".join(f"{v:.12e}" for v in p) + "\n")
        w(f"*ELEMENT, TYPE={etype}, ELSET=SPHERE\n")
        for e, c in enumerate(conn):
            w(f"{e + 1}, " + ", ".join(str(v + 1) for v in c) + "\n")
        w(f"*ELEMENT, TYPE={ptype}, ELSET=PLANE\n")
        for e, c in enumerate(pconn):
            w(f"{len(conn) + e + 1}, " + ", ".join(str(v + n + 1) for v in c) + "\n")
        _nset(f, "NPLANE", np.arange(n, n + len(pnodes)))
        _nset(f, "NSURF", surface_nodes)
        _nset(f, "NPATCH", patch_nodes)
        _nset(f, "NREF", [centre])
        w("*SURFACE, NAME=SSPHERE\n")
        for e, label, _ in faces:
            w(f"{e + 1}, S{label}\n")
        w("*SURFACE, NAME=SPLANE\n")
        for e in range(len(pconn)):
            w(f"{len(conn) + e + 1}, S{ptop}\n")
        w("*MATERIAL, NAME=ELASTIC\n*ELASTIC\n")
        w(f"{problem.youngs:.10g}, {problem.poisson:.10g}\n")
        w("*DENSITY\n1.\n")
        w("*SOLID SECTION, ELSET=SPHERE, MATERIAL=ELASTIC\n")
        w("*SOLID SECTION, ELSET=PLANE, MATERIAL=ELASTIC\n")
        # The plane is held fixed; symmetry conditions of the sphere.
        w(f"*BOUNDARY\nNPLANE, 1, {dim}\n")
        if dim == 2:
            _nset(f, "NAXIS", np.nonzero(np.abs(x[:, 0]) < tol)[0])
            w("*BOUNDARY\nNAXIS, 1, 1\n")
        else:
            _nset(f, "NSYMX", np.nonzero(np.abs(x[:, 0]) < tol)[0])
            _nset(f, "NSYMY", np.nonzero(np.abs(x[:, 1]) < tol)[0])
            w("*BOUNDARY\nNSYMX, 1, 1\nNSYMY, 2, 2\n")
        if len(equator):
            # The equator stays plane: its u_z follows the centre node, which is loaded.
            w("*EQUATION\n")
            for i in equator:
                if i != centre:
                    w(f"2\n{i + 1}, {dim}, 1., {centre + 1}, {dim}, -1.\n")
        w("*SURFACE INTERACTION, NAME=SI\n")
        w("*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n")
        w(f"{penalty:.6g}\n")
        pair = "SSPHERE, SPLANE" if slave == "sphere" else "SPLANE, SSPHERE"
        w(f"*CONTACT PAIR, INTERACTION=SI, TYPE=SURFACE TO SURFACE\n{pair}\n")
        solver_opt = f", SOLVER={solver}" if solver else ""
        # The load step, then `rematch` more steps at the same load: CalculiX matches
        # slave and master faces (integration points, normals, areas) once at the start
        # of an increment and keeps that while iterating, so each extra step redoes the
        # matching in the loaded configuration (the result then no longer depends on the
        # starting geometry).
        for k in range(1 + rematch):
            w("*STEP, INC=200" + (", NLGEOM" if nlgeom else "") + "\n")
            w(f"*STATIC{solver_opt}\n1., 1.\n")
            if k == 0:
                if loading == "body":
                    # Uniform body force ("gravity" with density 1) totalling P, downward.
                    down = "0., -1., 0." if dim == 2 else "0., 0., -1."
                    w(f"*DLOAD\nSPHERE, GRAV, {weight:.12g}, {down}\n")
                elif loading == "nodal":
                    w("*CLOAD\n")
                    for i, fz in zip(*nodal_forces):
                        if fz != 0.0:
                            w(f"{i + 1}, {dim}, {fz:.12e}\n")
                else:
                    w(f"*CLOAD\n{centre + 1}, {dim}, {-problem.load * load_share:.12g}\n")
            w("*NODE PRINT, NSET=NREF\nU\n")
            if k == rematch:
                w("*NODE PRINT, NSET=NPATCH\nU\n")
                w("*NODE PRINT, NSET=NPLANE, TOTALS=ONLY\nRF\n")
            w("*END STEP\n")
    return centre


def patch_nodes(conn, surface_nodes):
    """All nodes of the elements that touch a contact-surface node."""
    mark = np.zeros(conn.max() + 1, dtype=bool)
    mark[surface_nodes] = True
    touch = mark[conn].any(axis=1)
    return np.unique(conn[touch])

