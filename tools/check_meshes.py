#!/usr/bin/env python3
"""Checks the stored meshes of meshes/ and prints Markdown tables.

    python3 tools/check_meshes.py                 # every meshes/*.msh
    python3 tools/check_meshes.py meshes/a.msh ...

Reads each mesh with meshio (independent of gmsh) and reports, over its 3D
elements (hex8, tet4): node count, element counts by type (2D boundary
elements too), edge lengths (min/median/max over unique edges), the median
edge counted once per element (the grid spacing Δ that pdcontact takes by
default, src/case/discretize.rs `median_edge`), the total volume (exact for the
trilinear hexes: 2x2x2 Gauss integration of det J) against the exact volume
(4πR³/3 for a sphere, R = largest node radius; πR²L for a cylinder along y; the bounding
box for a box),
the minimum scaled Jacobian (Verdict definition: at each corner, the triple
product of the unit edge vectors; tets scaled so that the regular tet is 1)
and whether any element is inverted (det J <= 0 at a corner or Gauss point).

A second table checks conformity (interior faces shared by exactly two
elements, every free face on the outer boundary, no duplicate nodes) and the
grid at the south pole (0, 0, -R) of the spheres, where they touch the plane,
and the depth below the sphere (R - |x|) of the interior nodes joined to the
surface by an edge (the first node layer, which a surface detector must not
take for surface nodes).
With gmsh importable, gmsh's own minimum SICN and minimum det J (adaptive,
exact bounds) are added as a cross-check.

Exit status 1 when an element is inverted, a hex has a scaled Jacobian below
0.2, a node is duplicated or a free face lies inside the body.
"""
import glob
import itertools
import math
import os
import sys

import meshio
import numpy as np

HEX_EDGES = [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4),
             (0, 4), (1, 5), (2, 6), (3, 7)]
TET_EDGES = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]
HEX_FACES = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
TET_FACES = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
# corner, then its three neighbours in right-handed order (gmsh/VTK hex order)
HEX_CORNERS = [(0, 1, 3, 4), (1, 2, 0, 5), (2, 3, 1, 6), (3, 0, 2, 7),
               (4, 7, 5, 0), (5, 4, 6, 1), (6, 5, 7, 2), (7, 6, 4, 3)]
HEX_REF = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                    [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], float)
CORNERS_OF = {"tetra10": ("tetra", 4), "hexahedron20": ("hexahedron", 8), "hexahedron27": ("hexahedron", 8)}
SOLIDS = {"hexahedron": ("hex8", HEX_EDGES, HEX_FACES), "tetra": ("tet4", TET_EDGES, TET_FACES)}
NAMES = {"hexahedron": "hex8", "tetra": "tet4", "quad": "quad4", "triangle": "tri3",
         "wedge": "wedge6", "pyramid": "pyramid5", "line": "line2", "vertex": "point"}


def hex_dshape(xi):
    """Derivatives (8, 3) of the trilinear shape functions at xi."""
    r = HEX_REF
    return np.stack([
        r[:, 0] * (1 + r[:, 1] * xi[1]) * (1 + r[:, 2] * xi[2]),
        r[:, 1] * (1 + r[:, 0] * xi[0]) * (1 + r[:, 2] * xi[2]),
        r[:, 2] * (1 + r[:, 0] * xi[0]) * (1 + r[:, 1] * xi[1]),
    ], axis=1) / 8


def hex_metrics(x):
    """x: (n, 8, 3) -> scaled Jacobian, volume, min det J (corners and Gauss points)."""
    sj = np.full(len(x), np.inf)
    for c, i, j, k in HEX_CORNERS:
        e = [x[:, m] - x[:, c] for m in (i, j, k)]
        e = [v / np.linalg.norm(v, axis=1)[:, None] for v in e]
        sj = np.minimum(sj, np.einsum("ij,ij->i", e[0], np.cross(e[1], e[2])))
    g = 1 / math.sqrt(3)
    vol = np.zeros(len(x))
    detmin = np.full(len(x), np.inf)
    for xi in itertools.product((-g, g), repeat=3):  # exact: det J is degree 2 per variable
        det = np.linalg.det(np.einsum("nai,aj->nij", x, hex_dshape(np.array(xi))))
        vol += det
        detmin = np.minimum(detmin, det)
    for xi in HEX_REF:
        det = np.linalg.det(np.einsum("nai,aj->nij", x, hex_dshape(xi)))
        detmin = np.minimum(detmin, det)
    return sj, vol, detmin


def tet_metrics(x):
    """x: (n, 4, 3) -> scaled Jacobian (Verdict), volume, det J."""
    det = np.linalg.det(np.stack([x[:, 1] - x[:, 0], x[:, 2] - x[:, 0], x[:, 3] - x[:, 0]], axis=2))
    ln = lambda a, b: np.linalg.norm(x[:, a] - x[:, b], axis=1)
    corner = np.stack([ln(0, 1) * ln(0, 2) * ln(0, 3), ln(1, 0) * ln(1, 2) * ln(1, 3),
                       ln(2, 0) * ln(2, 1) * ln(2, 3), ln(3, 0) * ln(3, 1) * ln(3, 2)], axis=1)
    return math.sqrt(2) * det / corner.max(axis=1), det / 6, det


def gmsh_quality(path):
    """(min SICN, min det J) over the 3D elements, from gmsh, or None."""
    try:
        import gmsh
    except ImportError:
        return None
    gmsh.initialize(["gmsh", "-v", "0"])
    try:
        gmsh.open(path)
        sicn, detj = [], []
        for etype in gmsh.model.mesh.getElementTypes(3):
            tags, _ = gmsh.model.mesh.getElementsByType(etype)
            sicn.append(min(gmsh.model.mesh.getElementQualities(tags, "minSICN")))
            detj.append(min(gmsh.model.mesh.getElementQualities(tags, "minDetJac")))
        return min(sicn), min(detj), gmsh.__version__
    finally:
        gmsh.finalize()


def analyse(path):
    m = meshio.read(path, file_format="gmsh")
    p = m.points
    out = {"name": os.path.basename(path), "size": os.path.getsize(path), "nodes": len(p)}
    counts = {}
    for block in m.cells:
        counts[block.type] = counts.get(block.type, 0) + len(block.data)
    out["counts"] = counts
    groups = {}
    for name, blocks in m.cell_sets.items():
        if name.startswith("gmsh:"):
            continue
        n = sum(0 if b is None else len(b) for b in blocks)
        types = {m.cells[i].type for i, b in enumerate(blocks) if b is not None and len(b)}
        groups[name] = (n, "/".join(sorted(NAMES.get(t, t) for t in types)))
    out["groups"] = groups

    edges, per_elem, sj, vol, det, faces, solid_nodes = [], [], {}, 0.0, np.inf, {}, []
    for block in m.cells:
        # Second-order solids are checked on their corners (the particles by default).
        kind, corners = CORNERS_OF.get(block.type, (block.type, None))
        if kind not in SOLIDS:
            if block.data.ndim == 2 and block.type in ("wedge", "pyramid"):
                raise SystemExit(f"{path}: {block.type} elements are not checked here")
            continue
        short, e_list, f_list = SOLIDS[kind]
        c = block.data if corners is None else block.data[:, :corners]
        x = p[c]
        s, v, d = (hex_metrics if kind == "hexahedron" else tet_metrics)(x)
        sj[short] = min(sj.get(short, np.inf), s.min())
        out.setdefault("sj_below", {})[short] = out.get("sj_below", {}).get(short, 0) + int((s < 0.2).sum())
        vol += v.sum()
        det = min(det, d.min())
        e = np.concatenate([c[:, [a, b]] for a, b in e_list])
        per_elem.append(np.linalg.norm(p[e[:, 0]] - p[e[:, 1]], axis=1))
        edges.append(np.sort(e, axis=1))
        faces.setdefault(short, []).extend(np.sort(c[:, list(f)], axis=1) for f in f_list)
        solid_nodes.append(c.ravel())
    if not edges:
        raise SystemExit(f"{path}: no hex8 or tet4 elements")
    e = np.unique(np.concatenate(edges), axis=0)
    length = np.linalg.norm(p[e[:, 0]] - p[e[:, 1]], axis=1)
    out["edge"] = (length.min(), float(np.median(length)), length.max())
    out["delta"] = float(np.median(np.concatenate(per_elem)))
    out["volume"] = vol
    out["min_sj"] = sj
    out["inverted"] = bool(det <= 0)
    out["min_det"] = det

    used = np.unique(np.concatenate(solid_nodes))
    r = np.linalg.norm(p[used], axis=1)
    sphere = "ball" in groups
    cylinder = "roller" in groups  # axis y
    lo, hi = p[used].min(axis=0), p[used].max(axis=0)
    if sphere:
        radius = r.max()
        out["exact"], out["exact_what"] = 4 * math.pi * radius ** 3 / 3, f"4π/3·{radius:g}³"
    elif cylinder:
        radius = np.hypot(p[used, 0], p[used, 2]).max()
        length = hi[1] - lo[1]
        out["exact"], out["exact_what"] = math.pi * radius ** 2 * length, f"π·{radius:g}²·{length:g}"
    else:
        out["exact"], out["exact_what"] = float(np.prod(hi - lo)), "box"
    out["rel"] = out["volume"] / out["exact"] - 1

    # conformity: faces used once lie on the outer boundary, none used more than twice
    free, over = 0, 0
    off_boundary = 0
    for by_type in faces.values():  # hex faces are quads, tet faces triangles
        allf = np.concatenate(by_type)
        uniq, cnt = np.unique(allf, axis=0, return_counts=True)
        over += int((cnt > 2).sum())
        bf = uniq[cnt == 1]
        free += len(bf)
        q = p[bf.ravel()]
        if sphere:
            on = np.abs(np.linalg.norm(q, axis=1) - radius) < 1e-9 * radius
        elif cylinder:
            tol = 1e-9 * radius
            on = (np.abs(np.hypot(q[:, 0], q[:, 2]) - radius) < tol) | (np.abs(q[:, 1] - lo[1]) < tol) | (np.abs(q[:, 1] - hi[1]) < tol)
        else:
            tol = 1e-9 * np.linalg.norm(hi - lo)
            on = (np.abs(q - lo) < tol).any(axis=1) | (np.abs(q - hi) < tol).any(axis=1)
        off = (~on.reshape(len(bf), -1)).all(axis=1)
        if not (sphere or cylinder):
            # a shell sector (the quarter caps): its faces lie on spheres about the origin or
            # on planes through it
            qf = p[bf]
            norms = np.linalg.norm(qf, axis=2)
            on_sphere = np.ptp(norms, axis=1) < 1e-6 * norms.max(axis=1)
            n = np.cross(qf[:, 1] - qf[:, 0], qf[:, 2] - qf[:, 0])
            n /= np.linalg.norm(n, axis=1, keepdims=True)
            through_origin = np.abs((n * qf[:, 0]).sum(axis=1)) < tol
            off &= ~(on_sphere | through_origin)
        off_boundary += int(off.sum())
    out["free_faces"], out["over_faces"], out["free_inside"] = free, over, off_boundary
    key = np.round(p[used] / (1e-9 * max(1.0, np.abs(p).max())))
    out["duplicates"] = len(used) - len(np.unique(key, axis=0))

    if sphere:  # grid at the south pole
        surf = np.abs(np.linalg.norm(p, axis=1) - radius) < 1e-9 * radius
        pole = np.array([0, 0, -radius])
        i = int(np.argmin(np.linalg.norm(p - pole, axis=1)))
        inc = e[(e[:, 0] == i) | (e[:, 1] == i)]
        tang = [np.linalg.norm(p[a] - p[b]) for a, b in inc if surf[a] and surf[b]]
        inward = [np.linalg.norm(p[a] - p[b]) for a, b in inc if not (surf[a] and surf[b])]
        out["pole"] = (np.linalg.norm(p[i] - pole), len(tang), np.mean(tang), len(inward), np.mean(inward))
        # first node layer: interior nodes that share an edge with a surface node
        cross = e[surf[e[:, 0]] != surf[e[:, 1]]]
        first = np.unique(np.where(surf[cross[:, 0]], cross[:, 1], cross[:, 0]))
        depth = radius - np.linalg.norm(p[first], axis=1)
        out["first_layer"] = (depth.min(), depth.max())
    out["gmsh"] = gmsh_quality(path)
    return out


def fmt_counts(counts):
    order = ["hexahedron", "tetra", "wedge", "pyramid", "quad", "triangle", "line", "vertex"]
    keys = sorted(counts, key=lambda k: order.index(k) if k in order else 99)
    return ", ".join(f"{counts[k]} {NAMES.get(k, k)}" for k in keys)


def main(argv):
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    paths = argv or sorted(glob.glob(os.path.join(root, "meshes", "*.msh")))
    if not paths:
        raise SystemExit("no meshes found")
    rows = [analyse(path) for path in paths]
    bad = []

    print("| mesh | nodes | elements | edge min / median / max (m) | Δ (m) | volume (m³) | exact (m³) | rel. diff | min scaled Jacobian | inverted |")
    print("|---|--:|---|---|--:|--:|--:|--:|---|---|")
    for o in rows:
        sj = ", ".join(f"{v:.3f} ({k})" for k, v in o["min_sj"].items())
        print(f"| {o['name']} | {o['nodes']} | {fmt_counts(o['counts'])} | "
              f"{o['edge'][0]:.4f} / {o['edge'][1]:.4f} / {o['edge'][2]:.4f} | {o['delta']:.4f} | "
              f"{o['volume']:.5f} | {o['exact']:.5f} ({o['exact_what']}) | {100 * o['rel']:+.3f} % | "
              f"{sj} | {'YES' if o['inverted'] else 'no'} |")
        if o["inverted"]:
            bad.append(f"{o['name']}: inverted element (min det J {o['min_det']:.3e})")
        if o["min_sj"].get("hex8", 1.0) < 0.2:
            bad.append(f"{o['name']}: {o['sj_below']['hex8']} hex8 with scaled Jacobian < 0.2")
        if o["duplicates"] or o["over_faces"] or o["free_inside"]:
            bad.append(f"{o['name']}: not conforming ({o['duplicates']} duplicate nodes, "
                       f"{o['over_faces']} faces in > 2 elements, {o['free_inside']} free faces inside)")
    print()
    print("Δ: median edge counted once per element (pdcontact's default grid spacing is the lattice spacing of the particles' median volume, not this); "
          "edge min/median/max: over unique edges.")
    print()
    print("| mesh | size (bytes) | physical groups | free faces (all on the boundary) | duplicate nodes | south pole: node offset, surface edges, inward edges (m) | first node layer: depth min / max (m) | gmsh min SICN / min det J |")
    print("|---|--:|---|---|--:|---|---|---|")
    for o in rows:
        groups = ", ".join(f"{k} ({n} {t})" for k, (n, t) in o["groups"].items())
        free = f"{o['free_faces']} ({'yes' if o['free_inside'] == 0 else 'NO: %d inside' % o['free_inside']})"
        if "pole" in o:
            off, nt, t, ni, i = o["pole"]
            pole = f"{off:.1e}, {nt} × {t:.4f}, {ni} × {i:.4f}"
        else:
            pole = "–"
        first = f"{o['first_layer'][0]:.4f} / {o['first_layer'][1]:.4f}" if "first_layer" in o else "–"
        g = "–" if o["gmsh"] is None else f"{o['gmsh'][0]:.3f} / {o['gmsh'][1]:.2e} (gmsh {o['gmsh'][2]})"
        print(f"| {o['name']} | {o['size']} | {groups} | {free} | {o['duplicates']} | {pole} | {first} | {g} |")
    if bad:
        print()
        for b in bad:
            print("FAIL:", b)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
