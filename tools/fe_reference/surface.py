"""The sphere's contact surface, its undeformed nodal areas, and nodal pressures.

The contact surface is made of the element faces on the sphere r = R whose nodes all
lie below z = ``zcut`` (CalculiX's slave surface in 3D, its master in the axisymmetric
model). For each of its nodes the undeformed tributary area is the integral of the
node's face shape function over the faces it belongs to, A_i = sum_f int N_i dA (for
the axisymmetric model dA = 2 pi r ds). That is the area that turns a uniform pressure
into consistent nodal forces, F_i = p A_i. The consistent face "mass" matrix
M_ij = sum_f int N_i N_j dA is also built: p = M^-1 F is the pressure field, in the face
shape functions, whose consistent nodal forces are F.
"""
import numpy as np

# CalculiX face numbering: (face label, element-local node indices: corners then midsides).
CAX8_FACES = [(1, (0, 1, 4)), (2, (1, 2, 5)), (3, (2, 3, 6)), (4, (3, 0, 7))]
C3D10_FACES = [(1, (0, 1, 2, 4, 5, 6)), (2, (0, 3, 1, 7, 8, 4)),
               (3, (1, 3, 2, 8, 9, 5)), (4, (2, 3, 0, 9, 7, 6))]


def sphere_faces(x, conn, faces, radius, zcut):
    """[(element, face label, global node ids)] of element faces on the sphere, z < zcut."""
    on_sphere = np.abs(np.linalg.norm(x, axis=1) - radius) < 1e-9 * radius
    low = x[:, -1] < zcut
    out = []
    for label, local in faces:
        ids = conn[:, local]
        ok = np.all(on_sphere[ids] & low[ids], axis=1)
        for e in np.nonzero(ok)[0]:
            out.append((int(e), label, ids[e]))
    return out


def _gauss_line(n=5):
    return np.polynomial.legendre.leggauss(n)


def _line3(xi):
    return np.array([0.5 * xi * (xi - 1.0), 0.5 * xi * (xi + 1.0), 1.0 - xi * xi]), \
        np.array([xi - 0.5, xi + 0.5, -2.0 * xi])


# Radon's 7-point rule on the triangle (degree 5), weights summing to 1.
_S15 = np.sqrt(15.0)
_A1, _A2 = (6.0 - _S15) / 21.0, (6.0 + _S15) / 21.0
_TRI_L = np.array([[1 / 3, 1 / 3, 1 / 3],
                   [_A1, _A1, 1 - 2 * _A1], [_A1, 1 - 2 * _A1, _A1], [1 - 2 * _A1, _A1, _A1],
                   [_A2, _A2, 1 - 2 * _A2], [_A2, 1 - 2 * _A2, _A2], [1 - 2 * _A2, _A2, _A2]])
_TRI_W = np.array([9 / 40] + [(155 - _S15) / 1200] * 3 + [(155 + _S15) / 1200] * 3)


def _tri6(L):
    """Shape functions of the 6-node triangle (corners 1-3, midsides 12, 23, 31) and their
    derivatives with respect to s = L2, t = L3 (L1 = 1 - s - t)."""
    l1, l2, l3 = L
    n = np.array([l1 * (2 * l1 - 1), l2 * (2 * l2 - 1), l3 * (2 * l3 - 1),
                  4 * l1 * l2, 4 * l2 * l3, 4 * l3 * l1])
    dl = np.array([[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]])   # dL_k / d(s, t)
    dn_dl = np.array([[4 * l1 - 1, 0, 0], [0, 4 * l2 - 1, 0], [0, 0, 4 * l3 - 1],
                      [4 * l2, 4 * l1, 0], [0, 4 * l3, 4 * l2], [4 * l3, 0, 4 * l1]])
    return n, dn_dl @ dl


def face_matrices(x, faces):
    """(nodes, A, M, T): the slave node ids, their tributary areas, the (dense) matrix M,
    and for each node the total area of the faces it belongs to."""
    nodes = np.unique(np.concatenate([f[2] for f in faces]))
    where = {int(n): k for k, n in enumerate(nodes)}
    m = np.zeros((len(nodes), len(nodes)))
    touching = np.zeros(len(nodes))
    axisymmetric = x.shape[1] == 2
    if axisymmetric:
        xi, wi = _gauss_line()
        points = [(_line3(s), w) for s, w in zip(xi, wi)]
    else:
        points = [(_tri6(L), w * 0.5) for L, w in zip(_TRI_L, _TRI_W)]
    for _, _, ids in faces:
        xe = x[ids]
        loc = [where[int(n)] for n in ids]
        me = np.zeros((len(ids), len(ids)))
        for (n, dn), w in points:
            if axisymmetric:
                tangent = dn @ xe
                da = 2.0 * np.pi * (n @ xe)[0] * np.linalg.norm(tangent) * w
            else:
                j = dn.T @ xe                      # (2, 3): d x / d(s, t)
                da = np.linalg.norm(np.cross(j[0], j[1])) * w
            me += np.outer(n, n) * da
        m[np.ix_(loc, loc)] += me
        touching[loc] += me.sum()
    return nodes, m.sum(axis=1), m, touching


def pressures(force, area, m, method):
    """Nodal pressures from nodal normal forces: "lumped" p_i = F_i / A_i (the METHOD.md
    definition), or "consistent" p = M^-1 F."""
    if method == "lumped":
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(area > 0.0, force / area, np.nan)
    if method == "consistent":
        return np.linalg.solve(m, force)
    raise ValueError(method)

