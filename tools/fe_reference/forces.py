"""Element internal forces f = sum_e int B^T D B u_e dV of the linear-elastic sphere.

At a free node on the contact surface the internal force balances the contact force, so
f_int there IS the node's contact force. CalculiX's own reaction-force output cannot give
it: in the contact run it includes the contact springs (zero at free nodes). The element
routines follow CalculiX: C3D10 with its 4-point rule; CAX8, which CalculiX expands into
a 2-degree C3D20 wedge, as the axisymmetric 8-node quadrilateral with 3 x 3 Gauss points
(the wedge differs from it by terms of order (2 degrees)^2). Forces of the axisymmetric
model are for the whole circumference.
"""
import numpy as np


def _elasticity(youngs, poisson, axisymmetric):
    lam = youngs * poisson / ((1 + poisson) * (1 - 2 * poisson))
    mu = youngs / (2 * (1 + poisson))
    if axisymmetric:   # (e_r, e_z, e_theta, g_rz)
        d = np.full((3, 3), lam) + 2 * mu * np.eye(3)
        out = np.zeros((4, 4))
        out[:3, :3] = d
        out[3, 3] = mu
        return out
    out = np.zeros((6, 6))   # (xx, yy, zz, xy, yz, zx), engineering shears
    out[:3, :3] = lam
    out[:3, :3] += 2 * mu * np.eye(3)
    out[3:, 3:] = mu * np.eye(3)
    return out


def _quad8(xi, eta):
    """Shape functions and natural derivatives of the 8-node serendipity quadrilateral."""
    c = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], dtype=float)
    n = np.zeros(8)
    d = np.zeros((8, 2))
    for k, (a, b) in enumerate(c):
        n[k] = 0.25 * (1 + a * xi) * (1 + b * eta) * (a * xi + b * eta - 1)
        d[k, 0] = 0.25 * a * (1 + b * eta) * (2 * a * xi + b * eta)
        d[k, 1] = 0.25 * b * (1 + a * xi) * (a * xi + 2 * b * eta)
    for k, (a, b) in zip(range(4, 8), [(0, -1), (1, 0), (0, 1), (-1, 0)]):
        if a == 0:
            n[k] = 0.5 * (1 - xi * xi) * (1 + b * eta)
            d[k] = [-xi * (1 + b * eta), 0.5 * b * (1 - xi * xi)]
        else:
            n[k] = 0.5 * (1 + a * xi) * (1 - eta * eta)
            d[k] = [0.5 * a * (1 - eta * eta), -eta * (1 + a * xi)]
    return n, d


def _tet10(p):
    """Shape functions and derivatives (w.r.t. xi, eta, zeta) of the 10-node tetrahedron,
    Abaqus/CalculiX order; L1 = 1 - xi - eta - zeta, L2 = xi, L3 = eta, L4 = zeta."""
    xi, eta, zeta = p
    L = np.array([1 - xi - eta - zeta, xi, eta, zeta])
    dL = np.array([[-1, -1, -1], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
    edges = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]
    n = np.zeros(10)
    d = np.zeros((10, 3))
    for k in range(4):
        n[k] = L[k] * (2 * L[k] - 1)
        d[k] = (4 * L[k] - 1) * dL[k]
    for k, (i, j) in enumerate(edges):
        n[4 + k] = 4 * L[i] * L[j]
        d[4 + k] = 4 * (L[i] * dL[j] + L[j] * dL[i])
    return n, d


def _rule(axisymmetric):
    if axisymmetric:
        g, w = np.polynomial.legendre.leggauss(3)
        return [((a, b), wa * wb) for a, wa in zip(g, w) for b, wb in zip(g, w)]
    a, b = 0.1381966011250105, 0.5854101966249685
    return [((a, a, a), 1 / 24), ((b, a, a), 1 / 24), ((a, b, a), 1 / 24), ((a, a, b), 1 / 24)]


def internal_forces(x, conn, u, youngs, poisson, nonlinear=False):
    """Nodal internal forces (n_nodes, dim) of the elements ``conn`` for displacements u.

    ``nonlinear``: finite strain, as CalculiX's NLGEOM treats *ELASTIC (St Venant-Kirchhoff:
    second Piola-Kirchhoff stress linear in the Green-Lagrange strain); the forces are then
    int grad N : (F S) dV over the undeformed elements."""
    dim = x.shape[1]
    axisymmetric = dim == 2
    d = _elasticity(youngs, poisson, axisymmetric)
    xe = x[conn]                      # (m, k, dim)
    ue = u[conn]
    fe = np.zeros_like(ue)
    for p, w in _rule(axisymmetric):
        n, dn = _quad8(*p) if axisymmetric else _tet10(p)
        jac = np.einsum("kd,mke->mde", dn, xe)        # d x_e / d xi_d
        det = np.linalg.det(jac)
        if np.any(det <= 0):
            raise RuntimeError("element with non-positive Jacobian")
        g = np.einsum("med,kd->mke", np.linalg.inv(jac), dn)   # d N_k / d x_e
        grad = np.einsum("mke,mki->mie", g, ue)       # d u_i / d x_e
        if nonlinear:
            m = len(conn)
            if axisymmetric:   # components (r, z, theta)
                r = np.einsum("k,mk->m", n, xe[:, :, 0])
                ur = np.einsum("k,mk->m", n, ue[:, :, 0])
                big = np.zeros((m, 3, 3))
                big[:, :2, :2] = grad
                big[:, 2, 2] = ur / r
                dv = 2 * np.pi * r * det * w
            else:
                big = grad
                dv = det * w
            f_ = np.eye(3) + big
            green = 0.5 * (np.einsum("mji,mjk->mik", f_, f_) - np.eye(3))
            lam = youngs * poisson / ((1 + poisson) * (1 - 2 * poisson))
            mu = youngs / (2 * (1 + poisson))
            pk2 = lam * np.trace(green, axis1=1, axis2=2)[:, None, None] * np.eye(3) + 2 * mu * green
            pk1 = f_ @ pk2                                      # P_iJ
            if axisymmetric:
                fe[:, :, 0] += dv[:, None] * (np.einsum("mke,me->mk", g, pk1[:, 0, :2])
                                              + n[None, :] / r[:, None] * pk1[:, 2, 2][:, None])
                fe[:, :, 1] += dv[:, None] * np.einsum("mke,me->mk", g, pk1[:, 1, :2])
            else:
                fe += dv[:, None, None] * np.einsum("mke,mie->mki", g, pk1)
            continue
        if axisymmetric:
            r = np.einsum("k,mk->m", n, xe[:, :, 0])
            ur = np.einsum("k,mk->m", n, ue[:, :, 0])
            eps = np.stack([grad[:, 0, 0], grad[:, 1, 1], ur / r, grad[:, 0, 1] + grad[:, 1, 0]], 1)
            sig = eps @ d.T
            dv = 2 * np.pi * r * det * w
            # B^T sigma: radial row gets dN/dr s_r + N/r s_t + dN/dz t_rz; axial dN/dz s_z + dN/dr t_rz
            fe[:, :, 0] += dv[:, None] * (g[:, :, 0] * sig[:, None, 0] + n[None, :] / r[:, None] * sig[:, None, 2]
                                          + g[:, :, 1] * sig[:, None, 3])
            fe[:, :, 1] += dv[:, None] * (g[:, :, 1] * sig[:, None, 1] + g[:, :, 0] * sig[:, None, 3])
        else:
            eps = np.stack([grad[:, 0, 0], grad[:, 1, 1], grad[:, 2, 2],
                            grad[:, 0, 1] + grad[:, 1, 0], grad[:, 1, 2] + grad[:, 2, 1],
                            grad[:, 2, 0] + grad[:, 0, 2]], 1)
            s = eps @ d.T
            sig = np.empty((len(conn), 3, 3))
            sig[:, 0, 0], sig[:, 1, 1], sig[:, 2, 2] = s[:, 0], s[:, 1], s[:, 2]
            sig[:, 0, 1] = sig[:, 1, 0] = s[:, 3]
            sig[:, 1, 2] = sig[:, 2, 1] = s[:, 4]
            sig[:, 2, 0] = sig[:, 0, 2] = s[:, 5]
            fe += (det * w)[:, None, None] * np.einsum("mke,mie->mki", g, sig)
    f = np.zeros((len(x), dim))
    np.add.at(f, conn.reshape(-1), fe.reshape(-1, dim))
    return f


def nodal_volumes(x, conn):
    """int N_i dV of every node over the elements ``conn`` (of revolution, for the
    axisymmetric model): a uniform body force b gives the consistent nodal forces b V_i."""
    axisymmetric = x.shape[1] == 2
    xe = x[conn]
    ve = np.zeros(conn.shape)
    for p, w in _rule(axisymmetric):
        n, dn = _quad8(*p) if axisymmetric else _tet10(p)
        dv = np.linalg.det(np.einsum("kd,mke->mde", dn, xe)) * w
        if axisymmetric:
            dv = dv * 2 * np.pi * np.einsum("k,mk->m", n, xe[:, :, 0])
        ve += dv[:, None] * n[None, :]
    out = np.zeros(len(x))
    np.add.at(out, conn.reshape(-1), ve.reshape(-1))
    return out


def volume(x, conn):
    """Volume of the elements (of revolution, for the axisymmetric model)."""
    return float(nodal_volumes(x, conn).sum())
