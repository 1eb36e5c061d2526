#!/usr/bin/env python3
"""Write a volume mesh as an ANSYS CDB (MAPDL blocked archive, the layout CDWRITE writes).

Usage:
    python3 tools/mesh_to_cdb.py IN OUT.cdb [--tet4-as-185] [--check]

IN is any mesh meshio reads (gmsh .msh 2.2/4.1 ASCII or binary, .inp, .vtu, ...). Only the
3-D solids are written; surface and line elements are dropped, and so are nodes that no solid
uses. Nodes and elements are numbered 1..N in the order meshio gives them.

What is written:
  * ET records, one element type per shape:
      tet4   -> SOLID285 (4 nodes; with --tet4-as-185: SOLID185 collapsed I J K K L L L L)
      tet10  -> SOLID187 (I J K L, then mid-edges I-J J-K K-I I-L J-L K-L)
      hex8   -> SOLID185,  hex20 -> SOLID186 (ANSYS = VTK mid-edge order)
      wedge6 -> SOLID185 collapsed I J K K M N O O
      pyramid5 -> SOLID185 collapsed I J K L M M M M
  * NBLOCK,6,SOLID with format (3i9,6e21.13e3); trailing zero coordinates are left out, as
    MAPDL does.
  * EBLOCK,19,SOLID with format (19i9): material 1, the element's type, real 1, section 1,
    node count, element number, then the nodes (more than 8 continue on one more line).
  * One element component (CMBLOCK, ranges as `first -last`) per physical volume group of the
    source mesh, named after the group in upper case; with no groups, one named BODY.
  * One node component (CMBLOCK ... NODE) per physical surface group, the nodes of its faces
    (a load or a boundary set, as an ANSYS user names the nodes of a face).

--check reads OUT back with ansys-mapdl-reader (`pip install ansys-mapdl-reader`), an
independent CDB reader, and compares node coordinates, element types, node lists and element
volumes with the source mesh; it exits with status 1 on a mismatch.
"""
import argparse
import os
import re
import sys

import meshio
import numpy as np

# meshio cell type -> (ANSYS element number, nodes in the record, map from meshio order).
# meshio uses VTK node order, which is ANSYS's for these shapes (FORMATS.md §1.6, §1.7).
LAYOUT = {
    "tetra": (285, [0, 1, 2, 3]),
    "tetra10": (187, list(range(10))),
    "hexahedron": (185, list(range(8))),
    "hexahedron20": (186, list(range(20))),
    "wedge": (185, [0, 1, 2, 2, 3, 4, 5, 5]),
    "pyramid": (185, [0, 1, 2, 3, 4, 4, 4, 4]),
}
TET4_AS_185 = (185, [0, 1, 2, 2, 3, 3, 3, 3])
# ANSYS mid-edge slots and their edges (corner indices), FORMATS.md §1.7.
MID_EDGES = {
    187: [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)],
    186: [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4),
          (0, 4), (1, 5), (2, 6), (3, 7)],
}
ETYPE_NAMES = {185: "SOLID185", 186: "SOLID186", 187: "SOLID187", 285: "SOLID285"}


def fortran_e(v):
    """A real in Fortran 1P,E21.13E3: `-2.8749388208227E-001`, ` 1.0000000000000E+000`."""
    if v == 0.0:
        return " 0.0000000000000E+000"
    mant, exp = f"{v:.13E}".split("E")
    return f"{mant}E{int(exp):+04d}".rjust(21)


def ranges(ids):
    """Sorted ids as CMBLOCK items: runs become `first, -last`."""
    out, i = [], 0
    while i < len(ids):
        j = i
        while j + 1 < len(ids) and ids[j + 1] == ids[j] + 1:
            j += 1
        out.append(ids[i])
        if j > i:
            out.append(-ids[j])
        i = j + 1
    return out


def volume_groups(mesh):
    """{NAME: block-wise boolean masks} for the physical volume groups meshio found."""
    groups = {}
    for name, per_block in mesh.cell_sets.items():
        if name.startswith("gmsh:"):
            continue
        masks = []
        hit = False
        for block, sel in zip(mesh.cells, per_block):
            m = np.zeros(len(block.data), dtype=bool)
            if block.type in LAYOUT and sel is not None and len(sel):
                m[np.asarray(sel, dtype=int)] = True
                hit = True
            masks.append(m)
        if hit:
            groups[re.sub(r"[^A-Z0-9_]", "_", name.upper())[:32]] = masks
    return groups


def surface_groups(mesh):
    """{NAME: source node indices} for the physical groups of 2-D cells (faces)."""
    faces = {"triangle", "triangle6", "quad", "quad8", "quad9"}
    groups = {}
    for name, per_block in mesh.cell_sets.items():
        if name.startswith("gmsh:"):
            continue
        nodes = [
            np.asarray(block.data)[np.asarray(sel, dtype=int)].ravel()
            for block, sel in zip(mesh.cells, per_block)
            if block.type in faces and sel is not None and len(sel)
        ]
        if nodes:
            groups[re.sub(r"[^A-Z0-9_]", "_", name.upper())[:32]] = np.unique(np.concatenate(nodes))
    return groups


def collect(mesh, tet4_as_185):
    """Solids as (ansys element number, record node indices, meshio type, source nodes)."""
    blocks = []
    for block in mesh.cells:
        if block.type not in LAYOUT:
            continue
        ename, perm = LAYOUT[block.type]
        if block.type == "tetra" and tet4_as_185:
            ename, perm = TET4_AS_185
        blocks.append((block, ename, np.asarray(block.data)[:, perm]))
    return blocks


def write_cdb(mesh, out, source, tet4_as_185=False):
    blocks = collect(mesh, tet4_as_185)
    if not blocks:
        sys.exit(f"{source}: no 3-D solid elements (tetra, tetra10, hexahedron, ...)")
    used = np.unique(np.concatenate([b[2].ravel() for b in blocks]))
    number = np.zeros(len(mesh.points), dtype=np.int64)
    number[used] = np.arange(1, len(used) + 1)
    pts = np.zeros((len(mesh.points), 3))
    pts[:, : mesh.points.shape[1]] = mesh.points

    etypes = sorted({b[1] for b in blocks}, key=[b[1] for b in blocks].index)
    itype = {e: k + 1 for k, e in enumerate(etypes)}
    n_el = sum(len(b[0].data) for b in blocks)
    w = []
    w.append(f"/COM, written by mesh_to_cdb.py from {os.path.basename(source)}")
    w.append("/PREP7")
    for e in etypes:
        w.append(f"ET,{itype[e]:9d},{e}")
    n = len(used)
    w.append(f"NBLOCK,6,SOLID,{n:10d},{n:10d}")
    w.append("(3i9,6e21.13e3)")
    for k, p in zip(range(1, n + 1), pts[used]):
        xyz = list(p)
        while len(xyz) > 1 and xyz[-1] == 0.0:  # MAPDL leaves out trailing zeros
            xyz.pop()
        w.append(f"{k:9d}{0:9d}{0:9d}" + "".join(fortran_e(float(v)) for v in xyz))
    w.append("N,R5.3,LOC,       -1,")
    w.append(f"EBLOCK,19,SOLID,{n_el:10d},{n_el:10d}")
    w.append("(19i9)")
    elem = 0
    elem_ids = []  # per block: element numbers
    for block, ename, conn in blocks:
        ids = np.arange(elem + 1, elem + 1 + len(conn))
        elem_ids.append(ids)
        elem = ids[-1]
        t = itype[ename]
        for eid, nodes in zip(ids, number[conn]):
            rec = [1, t, 1, 1, 0, 0, 0, 0, len(nodes), 0, int(eid)] + [int(v) for v in nodes]
            w.append("".join(f"{v:9d}" for v in rec[:19]))
            if len(rec) > 19:
                w.append("".join(f"{v:9d}" for v in rec[19:]))
    w.append(f"{-1:9d}")

    groups = volume_groups(mesh)
    solid_blocks = [b for b in mesh.cells if b.type in LAYOUT]
    if groups:
        comps = {}
        for name, masks in groups.items():
            solid_masks = [m for b, m in zip(mesh.cells, masks) if b.type in LAYOUT]
            comps[name] = sorted(
                int(i) for ids, m in zip(elem_ids, solid_masks) for i in ids[m]
            )
    else:
        comps = {"BODY": list(range(1, n_el + 1))}
    assert len(solid_blocks) == len(elem_ids)
    for name, ids in comps.items():
        items = ranges(ids)
        w.append(f"CMBLOCK,{name:<8s},ELEM,{len(items):8d}  ! users element component definition")
        w.append("(8i10)")
        for i in range(0, len(items), 8):
            w.append("".join(f"{v:10d}" for v in items[i : i + 8]))
    for name, nodes in surface_groups(mesh).items():
        ids = sorted(int(number[i]) for i in nodes if number[i] > 0)
        if name in comps or not ids:
            continue
        items = ranges(ids)
        w.append(f"CMBLOCK,{name:<8s},NODE,{len(items):8d}  ! users node component definition")
        w.append("(8i10)")
        for i in range(0, len(items), 8):
            w.append("".join(f"{v:10d}" for v in items[i : i + 8]))
    w.append("/GO")
    w.append("FINISH")
    with open(out, "w", newline="\n") as f:
        f.write("\n".join(w) + "\n")
    return blocks, used, number, comps


# ---------------------------------------------------------------------------------------------
# --check: read OUT back with ansys-mapdl-reader and compare.

def tet_volume(x, c):
    a, b, cc, d = (x[c[:, k]] for k in range(4))
    return np.einsum("ij,ij->i", np.cross(b - a, cc - a), d - a) / 6.0


def hex_volume(x, c):
    """Hex volume as 6 tets around the 0-6 diagonal (exact for planar faces)."""
    tets = [(0, 1, 2, 6), (0, 2, 3, 6), (0, 3, 7, 6), (0, 7, 4, 6), (0, 4, 5, 6), (0, 5, 1, 6)]
    return sum(tet_volume(x, c[:, list(t)]) for t in tets)


def linear_volume(x, conn, kind):
    if kind in ("tetra", "tetra10"):
        return tet_volume(x, conn[:, :4])
    if kind in ("hexahedron", "hexahedron20"):
        return hex_volume(x, conn[:, :8])
    return None


def check(out, mesh, blocks, used, number, comps):
    try:
        from ansys.mapdl.reader import Archive
    except ImportError:
        sys.exit("--check needs ansys-mapdl-reader: python3 -m pip install ansys-mapdl-reader")
    arch = Archive(out)
    bad = []

    def say(ok, what):
        print(f"  {'ok ' if ok else 'BAD'} {what}")
        if not ok:
            bad.append(what)

    x_src = np.zeros((len(mesh.points), 3))
    x_src[:, : mesh.points.shape[1]] = mesh.points
    nnum = np.asarray(arch.nnum)
    say(np.array_equal(nnum, np.arange(1, len(used) + 1)), f"nodes: {len(nnum)} (source {len(used)})")
    x_cdb = np.zeros((len(used) + 1, 3))
    x_cdb[nnum] = np.asarray(arch.nodes)[:, :3]
    dx = np.abs(x_cdb[1:] - x_src[used]).max()
    say(dx < 1e-12 * max(1.0, np.abs(x_src).max()), f"node coordinates: largest difference {dx:.2e}")

    enum = np.asarray(arch.enum)
    n_el = sum(len(b[2]) for b in blocks)
    say(len(enum) == n_el and np.array_equal(enum, np.arange(1, n_el + 1)),
        f"elements: {len(enum)} (source {n_el})")
    ekey = {int(k[0]): int(k[1]) for k in np.asarray(arch.ekey)}
    raw = arch.elem  # per element: 10 header fields + nodes (mapdl-archive layout)
    e0 = 0
    vol_src_total = vol_cdb_total = 0.0
    for block, ename, conn in blocks:
        m = len(conn)
        rows = raw[e0 : e0 + m]
        types = {ekey[int(r[1])] for r in rows}
        say(types == {ename}, f"{block.type} x {m}: element type {sorted(types)} (wrote {ename})")
        nn = conn.shape[1]
        got = np.array([np.asarray(r[10 : 10 + nn], dtype=np.int64) for r in rows])
        say(np.array_equal(got, number[conn]), f"{block.type}: node lists match")
        v_src = linear_volume(x_src, np.asarray(block.data), block.type)
        if v_src is not None:
            # the CDB's corners, back in source order, at the CDB's coordinates
            cdb_corners = got[:, [0, 1, 2, 4]] if ename == 185 and block.type == "tetra" else got
            v_cdb = linear_volume(x_cdb, cdb_corners, block.type)
            vol_src_total += v_src.sum()
            vol_cdb_total += v_cdb.sum()
            # the coordinates carry 14 significant digits: volumes agree to about 1e-12
            rel = np.abs(v_cdb / v_src - 1).max()
            say(rel < 1e-9 and (v_cdb > 0).all(),
                f"{block.type}: element volumes match (largest relative difference {rel:.1e}), "
                f"all positive (min {v_cdb.min():.3e}, total {v_cdb.sum():.6f})")
        e0 += m
    # Mid-edge nodes: each must lie nearest the midpoint of the edge the ANSYS node order
    # gives its slot (SOLID187: M..R on I-J J-K K-I I-L J-L K-L; SOLID186: Q..B).
    for block, ename, conn in blocks:
        edges = MID_EDGES.get(ename if conn.shape[1] > 8 or ename == 187 else None)
        if edges is None:
            continue
        c = number[conn]
        mids = np.stack([(x_cdb[c[:, a]] + x_cdb[c[:, b]]) / 2 for a, b in edges], axis=1)
        slot = x_cdb[c[:, len(c[0]) - len(edges):]]
        d = np.linalg.norm(slot[:, :, None, :] - mids[:, None, :, :], axis=3)
        ok = (d.argmin(axis=2) == np.arange(len(edges))).all()
        say(ok, f"{block.type}: every mid-edge node lies nearest its ANSYS edge's midpoint")
    # The reader's own VTK grid: per-cell volumes against the source's cells, through the same
    # VTK cell types (pyvista.from_meshio), so quadratic cells compare like with like.
    try:
        import pyvista as pv
        grid = arch.grid
        vol = grid.compute_cell_sizes(length=False, area=False).cell_data["Volume"]
        solids = meshio.Mesh(mesh.points, [(b.type, b.data) for b in mesh.cells
                                            if b.type in LAYOUT])
        src = pv.from_meshio(solids).compute_cell_sizes(length=False, area=False)
        v_src = src.cell_data["Volume"]
        print(f"  ..  reader's grid: {grid.n_points} points, {grid.n_cells} cells, "
              f"volume {vol.sum():.9f} (source {v_src.sum():.9f})")
        say(len(vol) == len(v_src) and np.allclose(vol, v_src, rtol=1e-9, atol=0),
            "reader's VTK cells have the source's volumes, cell by cell")
    except ImportError as err:
        print(f"  ..  reader's grid not checked: {err}")
    for name, ids in comps.items():
        got = np.asarray(arch.element_components.get(name, []))
        say(np.array_equal(np.sort(got), np.asarray(ids)), f"component {name}: {len(got)} elements")
    for name, nodes in surface_groups(mesh).items():
        if name in comps:
            continue
        want = np.sort(number[nodes][number[nodes] > 0])
        got = np.sort(np.asarray(arch.node_components.get(name, [])))
        say(np.array_equal(got, want), f"node component {name}: {len(got)} nodes")
    return not bad


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("input")
    ap.add_argument("output")
    ap.add_argument("--tet4-as-185", action="store_true",
                    help="write 4-node tets as collapsed SOLID185 (I J K K L L L L)")
    ap.add_argument("--check", action="store_true",
                    help="read OUT back with ansys-mapdl-reader and compare")
    a = ap.parse_args()
    mesh = meshio.read(a.input)
    blocks, used, number, comps = write_cdb(mesh, a.output, a.input, a.tet4_as_185)
    counts = {}
    for block, ename, conn in blocks:
        key = f"{block.type}->{ETYPE_NAMES.get(ename, ename)}"
        counts[key] = counts.get(key, 0) + len(conn)
    print(f"{a.output}: {len(used)} nodes, "
          + ", ".join(f"{v} {k}" for k, v in counts.items())
          + ", components " + ", ".join(f"{k} ({len(v)})" for k, v in comps.items()))
    if a.check:
        ok = check(a.output, mesh, blocks, used, number, comps)
        print("check:", "passed" if ok else "FAILED")
        sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
