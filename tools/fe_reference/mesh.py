"""gmsh meshes of the sphere, graded toward the contact at the south pole.

* ``axisymmetric``: the quarter disc r in [0, R], z in [-R, 0] (the lower half of the
  meridian section), 8-node quadrilaterals (CAX8).
* ``quarter``: the lower hemisphere cut by the planes x = 0 and y = 0 (one eighth of the
  ball), 10-node tetrahedra (C3D10).

The element size is ``h`` within ``fine`` of the contact point (0, 0, -R) and grows
linearly with the distance beyond that (slope ``growth``) up to ``hmax``. Midside nodes
of boundary edges lie on the sphere. Connectivities are returned in Abaqus/CalculiX
order (found by matching each midside node to its edge, not assumed), 0-based.
"""
import math

import numpy as np

import gmsh

# Abaqus edge order of the midside nodes.
QUAD8_EDGES = [(0, 1), (1, 2), (2, 3), (3, 0)]
TET10_EDGES = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]


def _midside_order(x, conn, ncorner, edges):
    """Reorder the midside nodes of ``conn`` so that node ncorner+k sits on edges[k]."""
    out = conn.copy()
    mids = conn[:, ncorner:]
    for k, (i, j) in enumerate(edges):
        target = 0.5 * (x[conn[:, i]] + x[conn[:, j]])
        d = np.linalg.norm(x[mids] - target[:, None, :], axis=2)
        out[:, ncorner + k] = mids[np.arange(len(conn)), np.argmin(d, axis=1)]
    if np.any(np.sort(out[:, ncorner:], axis=1) != np.sort(mids, axis=1)):
        raise RuntimeError("could not match midside nodes to edges")
    return out


def _size_field(point_tag, h, hmax, fine, growth, centre=None):
    """Size h within `fine` of the geometry point `point_tag` (or of the point `centre`, for a
    geometry without a vertex there), growing with slope `growth` to hmax."""
    f = gmsh.model.mesh.field
    if centre is None:
        d = f.add("Distance")
        f.setNumbers(d, "PointsList", [point_tag])
    else:
        d = f.add("MathEval")
        x, y, z = centre
        f.setString(d, "F", f"Sqrt((x-({x}))*(x-({x})) + (y-({y}))*(y-({y})) + (z-({z}))*(z-({z})))")
    t = f.add("Threshold")
    f.setNumber(t, "InField", d)
    f.setNumber(t, "SizeMin", h)
    f.setNumber(t, "SizeMax", hmax)
    f.setNumber(t, "DistMin", fine)
    f.setNumber(t, "DistMax", fine + (hmax - h) / growth)
    f.setAsBackgroundMesh(t)
    for opt in ("Mesh.MeshSizeExtendFromBoundary", "Mesh.MeshSizeFromPoints",
                "Mesh.MeshSizeFromCurvature"):
        gmsh.option.setNumber(opt, 0)


def _vertex_at(p, tol=1e-6):
    tags = gmsh.model.getEntitiesInBoundingBox(
        p[0] - tol, p[1] - tol, p[2] - tol, p[0] + tol, p[1] + tol, p[2] + tol, 0)
    if len(tags) != 1:
        raise RuntimeError(f"expected one vertex at {p}, found {tags}")
    return tags[0][1]


def _nodes_and(dim, etype, nper):
    tags, coords, _ = gmsh.model.mesh.getNodes()
    x = coords.reshape(-1, 3)
    types, _, enodes = gmsh.model.mesh.getElements(dim)
    if list(types) != [etype]:
        raise RuntimeError(f"unexpected element types {list(types)}")
    index = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
    index[tags] = np.arange(len(tags))
    conn = index[np.asarray(enodes[0], dtype=np.int64).reshape(-1, nper)]
    # Keep only the nodes the elements use (drops nothing here, but be safe).
    used = np.unique(conn)
    renum = np.full(len(x), -1, dtype=np.int64)
    renum[used] = np.arange(len(used))
    return x[used], renum[conn]


def axisymmetric(h, radius=1.0, hmax=0.08, fine=0.22, growth=0.3, full=False):
    """Returns (x (n, 2) with x = r, y = z; conn (m, 8) CAX8). ``full``: the whole
    meridian half-disc (z in [-R, R]) instead of its lower half."""
    gmsh.initialize(["-nt", "1"])
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("axisymmetric")
        g = gmsh.model.geo
        o = g.addPoint(0, 0, 0)
        s = g.addPoint(0, -radius, 0)
        e = g.addPoint(radius, 0, 0)
        if full:
            n = g.addPoint(0, radius, 0)
            loop = [g.addLine(n, o), g.addLine(o, s), g.addCircleArc(s, o, e),
                    g.addCircleArc(e, o, n)]
        else:
            loop = [g.addLine(o, s), g.addCircleArc(s, o, e), g.addLine(e, o)]
        g.addPlaneSurface([g.addCurveLoop(loop)])
        g.synchronize()
        _size_field(s, h, hmax, fine, growth)
        gmsh.option.setNumber("Mesh.Algorithm", 8)            # frontal-Delaunay for quads
        gmsh.option.setNumber("Mesh.RecombinationAlgorithm", 1)
        gmsh.option.setNumber("Mesh.RecombineAll", 1)
        gmsh.option.setNumber("Mesh.SecondOrderIncomplete", 1)
        gmsh.model.mesh.generate(2)
        gmsh.model.mesh.setOrder(2)
        x, conn = _nodes_and(2, 16, 8)
    finally:
        gmsh.finalize()
    x = x[:, :2]
    x[np.abs(x[:, 0]) < 1e-12, 0] = 0.0
    x[np.abs(x[:, 1]) < 1e-12, 1] = 0.0
    conn = _midside_order(x, conn, 4, QUAD8_EDGES)
    return x, conn


def quarter(h, radius=1.0, hmax=0.12, fine=0.2, growth=0.3, full=False):
    """Returns (x (n, 3); conn (m, 10) C3D10) of the octant x, y >= 0, z <= 0, or with
    ``full`` of the quarter x, y >= 0."""
    gmsh.initialize(["-nt", "1"])
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("quarter")
        occ = gmsh.model.occ
        ball = occ.addSphere(0, 0, 0, radius)
        # The sphere's parametrisation is singular at its poles (+-z): turn them to
        # +-(1, -1, 0)/sqrt 2, outside the quarter, so the contact point is regular.
        occ.rotate([(3, ball)], 0, 0, 0, 1.0, 1.0, 0.0, 0.5 * math.pi)
        box = occ.addBox(0, 0, -2 * radius, 2 * radius, 2 * radius,
                         (4 if full else 2) * radius)
        occ.intersect([(3, ball)], [(3, box)])
        occ.synchronize()
        _size_field(_vertex_at((0.0, 0.0, -radius)), h, hmax, fine, growth)
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
    conn = _midside_order(x, conn, 4, TET10_EDGES)
    return x, conn
