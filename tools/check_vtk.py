#!/usr/bin/env python3
"""Check pdcontact's VTK output with VTK's own readers (not with the writer that made it).

    python3 tools/check_vtk.py case DIR            # a `pdcontact convert` folder
    python3 tools/check_vtk.py run DIR [--plane-normal 0,0,1] [--plane-point 0,0,-1]
    python3 tools/check_vtk.py same DIR_A DIR_B    # two runs of a scene, e.g. 1 process and N ranks

`case`: particles.vtu and segments.vtu load with vtkXMLUnstructuredGridReader and hold the
fields `convert` documents.

`run`: run.pvd is parsed with VTK's XML parser (vtkXMLDataParser; plain VTK has no .pvd
reader, ParaView's pvpython does and is used when present), its timesteps increase, every
frame it lists (a .vtm) loads with vtkXMLMultiBlockDataReader with every block named
(`<body>/particles`, `<body>/surface`, rigid bodies by their name), each frame holds the field
data `load_factor` (ADR; timesteps in (0, 1]) or `time` (explicit; equal to the timestep), the
particles hold every documented field, each surface block holds only the nodes its cells use,
each a particle with the particle's values, `contact_pressure` (recovered) is positive exactly
where `particle_pressure` (each particle's own) is, and `contact_pressure` is positive only on
particles that face the rigid plane (outward normal against the plane normal) and whose
deformed positions (points + displacement) lie on it. A decomposed run's particles (one piece
per rank, a multi-piece block) are taken in piece order, and its `.pvtu` files must load with
vtkXMLPUnstructuredGridReader and hold the same points and values.

`same`: the two runs list the same timesteps, and every frame's blocks hold the same points and
point arrays, bit for bit (pieces put together in order): every particle once.

Prints a JSON report; exits 1 when a check fails, 2 when VTK is missing.
"""
import json
import os
import sys

try:
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy
    import numpy as np
except ImportError as e:  # pragma: no cover
    print(json.dumps({"ok": False, "error": f"python vtk/numpy missing: {e}"}))
    sys.exit(2)


def read_vtu(path):
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    if r.GetErrorCode() != 0:
        raise RuntimeError(f"{path}: VTK reader error code {r.GetErrorCode()}")
    g = r.GetOutput()
    if g is None or g.GetNumberOfPoints() == 0:
        raise RuntimeError(f"{path}: no points read")
    return g


def fields(data):
    return {data.GetArrayName(k): data.GetArray(k).GetNumberOfComponents() for k in range(data.GetNumberOfArrays())}


def require(found, wanted, where):
    missing = [f"{n}({c})" for n, c in wanted.items() if found.get(n) != c]
    if missing:
        raise RuntimeError(f"{where}: missing or wrong fields: {', '.join(missing)} (found {found})")


def check_case(folder):
    p = read_vtu(os.path.join(folder, "particles.vtu"))
    require(fields(p.GetPointData()),
            {"volume": 1, "lambda_min": 1, "surface": 1, "normal": 3, "node_id": 1, "boundary_node": 1},
            "particles.vtu")
    s = read_vtu(os.path.join(folder, "segments.vtu"))
    require(fields(s.GetCellData()), {"area": 1, "normal": 3}, "segments.vtu")
    if s.GetNumberOfCells() == 0:
        raise RuntimeError("segments.vtu: no cells")
    return {"particles": p.GetNumberOfPoints(), "segments": s.GetNumberOfCells(),
            "vertex_cells": p.GetNumberOfCells()}


def pvd_entries(path):
    parser = vtk.vtkXMLDataParser()
    parser.SetFileName(path)
    if not parser.Parse():
        raise RuntimeError(f"{path}: VTK's XML parser rejects it")
    root = parser.GetRootElement()
    if root.GetAttribute("type") != "Collection":
        raise RuntimeError(f"{path}: not a VTK Collection")
    coll = root.FindNestedElementWithName("Collection")
    out = []
    for k in range(coll.GetNumberOfNestedElements()):
        e = coll.GetNestedElement(k)
        out.append((float(e.GetAttribute("timestep")), int(e.GetAttribute("part") or 0), e.GetAttribute("file")))
    if not out:
        raise RuntimeError(f"{path}: empty collection")
    return out


def check_pvpython(path):
    """Open the .pvd with ParaView's own reader when pvpython is installed."""
    import shutil
    import subprocess
    exe = shutil.which("pvpython")
    if not exe:
        return None
    code = ("from paraview.simple import *; r = PVDReader(FileName=%r); r.UpdatePipeline(); "
            "print(len(r.TimestepValues))" % path)
    out = subprocess.run([exe, "-c", code], capture_output=True, text=True, timeout=300)
    if out.returncode != 0:
        raise RuntimeError(f"pvpython cannot open {path}: {out.stderr.strip()[-300:]}")
    return int(out.stdout.strip().splitlines()[-1])


def read_vtm(path):
    """A frame: {block path: unstructured grid}, e.g. {"ball/particles": ..., "plane": ...}."""
    r = vtk.vtkXMLMultiBlockDataReader()
    r.SetFileName(path)
    r.Update()
    if r.GetErrorCode() != 0:
        raise RuntimeError(f"{path}: VTK reader error code {r.GetErrorCode()}")
    out = {}

    def walk(mb, prefix):
        for k in range(mb.GetNumberOfBlocks()):
            meta = mb.GetMetaData(k) if mb.HasMetaData(k) else None
            name = meta.Get(vtk.vtkCompositeDataSet.NAME()) if meta is not None else None
            if not name:
                raise RuntimeError(f"{path}: block {prefix}{k} has no name")
            b = mb.GetBlock(k)
            if b is None:
                raise RuntimeError(f"{path}: block {prefix}{name} did not load")
            if b.IsA("vtkMultiBlockDataSet"):
                walk(b, prefix + name + "/")
                continue
            if b.IsA("vtkMultiPieceDataSet"):
                b = merge_pieces(b, f"{path}: {prefix}{name}")
            if b.GetNumberOfPoints() == 0:
                raise RuntimeError(f"{path}: block {prefix}{name} has no points")
            out[prefix + name] = b

    walk(r.GetOutput(), "")
    return out


def merge_pieces(mp, where):
    """The pieces of a multi-piece block, one grid, in piece order (no points merged)."""
    app = vtk.vtkAppendFilter()
    for q in range(mp.GetNumberOfPieces()):
        g = mp.GetPiece(q)
        if g is None:
            raise RuntimeError(f"{where}: piece {q} did not load")
        app.AddInputData(g)
    app.Update()
    out = vtk.vtkUnstructuredGrid()
    out.ShallowCopy(app.GetOutput())
    # vtkAppendFilter drops field data: keep the first piece's (load_factor, time, ...).
    out.SetFieldData(mp.GetPiece(0).GetFieldData())
    return out


def check_pvtu(folder, frames):
    """Every .pvtu of the frames loads and equals its frame's pieces; returns how many."""
    n = 0
    for vtm, blocks in frames:
        stem = vtm[: -len(".vtm")]
        d = os.path.join(folder, stem)
        for f in sorted(os.listdir(d)) if os.path.isdir(d) else []:
            if not f.endswith("_particles.pvtu"):
                continue
            r = vtk.vtkXMLPUnstructuredGridReader()
            r.SetFileName(os.path.join(d, f))
            r.Update()
            if r.GetErrorCode() != 0:
                raise RuntimeError(f"{stem}/{f}: VTK reader error code {r.GetErrorCode()}")
            body = f[: -len("_particles.pvtu")]
            g = blocks.get(f"{body}/particles")
            if g is None:
                raise RuntimeError(f"{stem}/{f}: no block {body}/particles in {vtm}")
            same_grid(r.GetOutput(), g, f"{stem}/{f}")
            n += 1
    return n


def same_grid(a, b, where):
    """Same points and point arrays, bit for bit."""
    if a.GetNumberOfPoints() != b.GetNumberOfPoints():
        raise RuntimeError(f"{where}: {a.GetNumberOfPoints()} points against {b.GetNumberOfPoints()}")
    pa, pb = (vtk_to_numpy(g.GetPoints().GetData()) for g in (a, b))
    if not np.array_equal(pa, pb):
        raise RuntimeError(f"{where}: points differ")
    fa, fb = fields(a.GetPointData()), fields(b.GetPointData())
    if fa != fb:
        raise RuntimeError(f"{where}: point arrays {sorted(fa)} against {sorted(fb)}")
    for n in fa:
        x = vtk_to_numpy(a.GetPointData().GetArray(n))
        y = vtk_to_numpy(b.GetPointData().GetArray(n))
        if not np.array_equal(x, y):
            raise RuntimeError(f"{where}: `{n}` differs by up to {float(np.abs(x - y).max()):.3e}")


def check_same(a, b):
    ea, eb = pvd_entries(os.path.join(a, "run.pvd")), pvd_entries(os.path.join(b, "run.pvd"))
    ta, tb = [t for t, _, _ in ea], [t for t, _, _ in eb]
    if ta != tb:
        raise RuntimeError(f"timesteps differ: {ta} against {tb}")
    points = 0
    for (_, _, fa), (_, _, fb) in zip(ea, eb):
        ba, bb = read_vtm(os.path.join(a, fa)), read_vtm(os.path.join(b, fb))
        if sorted(ba) != sorted(bb):
            raise RuntimeError(f"{fa}: blocks {sorted(ba)} against {sorted(bb)}")
        for k in ba:
            same_grid(ba[k], bb[k], f"{fa} {k}")
            points += ba[k].GetNumberOfPoints()
    return {"frames": len(ea), "points_compared": points}


def field_value(g, name):
    a = g.GetFieldData().GetArray(name)
    return None if a is None else float(a.GetValue(0))


def deformed(g):
    """Points + displacement: the deformed positions (the points are the reference)."""
    pos = vtk_to_numpy(g.GetPoints().GetData()).astype(float)
    d = g.GetPointData().GetArray("displacement")
    if d is None:
        raise RuntimeError("a block without point data `displacement`")
    return pos + vtk_to_numpy(d)


def check_surface(name, s, p):
    """The surface block: only the nodes its cells use, the particles' values there."""
    used = set()
    for c in range(s.GetNumberOfCells()):
        ids = s.GetCell(c).GetPointIds()
        used.update(ids.GetId(j) for j in range(ids.GetNumberOfIds()))
    if len(used) != s.GetNumberOfPoints():
        raise RuntimeError(f"{name}/surface: {s.GetNumberOfPoints()} points, its cells use {len(used)}")
    require(fields(s.GetPointData()), {"displacement": 3, "velocity": 3, "force": 3, "contact_force": 3,
                                       "contact_pressure": 1, "surface": 1, "normal": 3}, f"{name}/surface")
    # Each surface node is a particle: same reference position, same values.
    ppos = vtk_to_numpy(p.GetPoints().GetData()).astype(float)
    spos = vtk_to_numpy(s.GetPoints().GetData()).astype(float)
    loc = vtk.vtkPointLocator()
    loc.SetDataSet(p)
    loc.BuildLocator()
    idx = np.array([loc.FindClosestPoint(x) for x in spos])
    gap = float(np.abs(ppos[idx] - spos).max())
    if gap > 1e-9 * max(1.0, float(np.abs(ppos).max())):
        raise RuntimeError(f"{name}/surface: a node is {gap:.3e} from every particle")
    for f in ("contact_pressure", "displacement"):
        a = vtk_to_numpy(s.GetPointData().GetArray(f))
        b = vtk_to_numpy(p.GetPointData().GetArray(f))[idx]
        if not np.array_equal(a, b):
            raise RuntimeError(f"{name}/surface: `{f}` differs from the particles'")
    return int(len(used))


def check_run(folder, normal, point):
    pvd = os.path.join(folder, "run.pvd")
    entries = pvd_entries(pvd)
    times = [t for t, _, _ in entries]
    if any(b <= a for a, b in zip(times, times[1:])):
        raise RuntimeError(f"{pvd}: timesteps not increasing: {times}")
    frames = [read_vtm(os.path.join(folder, f)) for _, _, f in entries]
    pvtu = check_pvtu(folder, [(f, b) for (_, _, f), b in zip(entries, frames)])
    last = entries[-1][2]
    blocks = frames[-1]
    bodies = sorted({k.split("/")[0] for k in blocks if k.endswith("/particles")})
    if not bodies:
        raise RuntimeError(f"{last}: no `<body>/particles` block (blocks {sorted(blocks)})")
    report = {"pvd_entries": len(entries), "frames": len(frames), "last": last,
              "blocks": sorted(blocks), "first_timestep": times[0], "last_timestep": times[-1],
              "pvtu": pvtu}
    g0 = next(iter(blocks.values()))
    lf, t = field_value(g0, "load_factor"), field_value(g0, "time")
    if lf is None and t is None:
        raise RuntimeError(f"{last}: no field data `load_factor` or `time`")
    report["load_factor"] = lf
    report["time"] = t
    if t is not None and abs(t - times[-1]) > 1e-9 * max(1.0, abs(t)):
        raise RuntimeError(f"{last}: field data time {t} but .pvd timestep {times[-1]}")
    if lf is not None and not 0.0 < times[-1] <= 1.0 + 1e-12:
        raise RuntimeError(f"{pvd}: ADR timestep {times[-1]} outside (0, 1]")
    pos, pressure, nrm, count, surface_points = [], [], [], 0, 0
    for b in bodies:
        g = blocks[f"{b}/particles"]
        pd = g.GetPointData()
        require(fields(pd), {"displacement": 3, "velocity": 3, "force": 3, "contact_force": 3,
                             "contact_pressure": 1, "particle_pressure": 1, "surface": 1, "normal": 3, "body": 1,
                             "stress": 9, "von_mises": 1},
                f"{last}: {b}/particles")
        # The stress: a symmetric tensor, and von Mises recomputed from it here.
        sig = vtk_to_numpy(pd.GetArray("stress")).reshape(-1, 3, 3)
        if not np.allclose(sig, sig.transpose(0, 2, 1), rtol=1e-12, atol=1e-9 * max(1.0, np.abs(sig).max())):
            raise RuntimeError(f"{last}: {b}: stress is not symmetric")
        dev = sig - np.trace(sig, axis1=1, axis2=2)[:, None, None] / 3.0 * np.eye(3)
        vm = np.sqrt(1.5 * (dev * dev).sum(axis=(1, 2)))
        if not np.allclose(vm, vtk_to_numpy(pd.GetArray("von_mises")), rtol=1e-9, atol=1e-9 * max(1.0, vm.max())):
            raise RuntimeError(f"{last}: {b}: von_mises is not the stress's")
        if f"{b}/surface" not in blocks:
            raise RuntimeError(f"{last}: no block {b}/surface")
        surface_points += check_surface(b, blocks[f"{b}/surface"], g)
        s = blocks[f"{b}/surface"]
        sp = vtk_to_numpy(s.GetPointData().GetArray("contact_pressure"))
        count += int((sp > 0).sum())
        pos.append(deformed(g))
        pressure.append(vtk_to_numpy(pd.GetArray("contact_pressure")))
        own = vtk_to_numpy(pd.GetArray("particle_pressure"))
        # The recovered pressure keeps the particles' own contact: loaded where they are.
        if not np.array_equal(pressure[-1] > 0, own > 0):
            raise RuntimeError(f"{last}: {b}: contact_pressure and particle_pressure load different particles")
        nrm.append(vtk_to_numpy(pd.GetArray("normal")))
    pos, pressure, nrm = np.concatenate(pos), np.concatenate(pressure), np.concatenate(nrm)
    loaded = pressure > 0
    report.update({"particles": int(len(pos)), "loaded": int(loaded.sum()),
                   "surface_points": surface_points, "surface_loaded": count})
    if loaded.any() and count != int(loaded.sum()):
        raise RuntimeError(f"{last}: {int(loaded.sum())} loaded particles but {count} loaded surface nodes")
    rigid = [k for k in blocks if "/" not in k]
    report["rigid_blocks"] = rigid
    if normal is not None:
        n = np.array(normal, float)
        n /= np.linalg.norm(n)
        facing = nrm @ n < -0.5
        bad = loaded & ~facing
        report["loaded_not_facing"] = int(bad.sum())
        if point is not None:
            height = (pos - np.array(point, float)) @ n
            report["max_height_of_loaded"] = float(np.abs(height[loaded]).max()) if loaded.any() else 0.0
            # The rigid plane, deformed (points + displacement), through `point`.
            report["plane_offset"] = max((float(np.abs((deformed(blocks[k]) - np.array(point, float)) @ n).max())
                                          for k in rigid), default=None)
        if not loaded.any():
            raise RuntimeError(f"{last}: no particle carries contact pressure")
        if bad.any():
            raise RuntimeError(f"{last}: {int(bad.sum())} loaded particles do not face the plane")
    pv = check_pvpython(pvd)
    report["pvpython_timesteps"] = pv
    return report


def parse_vec(s):
    return [float(x) for x in s.split(",")]


def main(argv):
    if len(argv) < 3 or argv[1] not in ("case", "run", "same") or (argv[1] == "same" and len(argv) < 4):
        print(__doc__)
        return 2
    try:
        if argv[1] == "case":
            report = check_case(argv[2])
        elif argv[1] == "same":
            report = check_same(argv[2], argv[3])
        else:
            normal = point = None
            if "--plane-normal" in argv:
                normal = parse_vec(argv[argv.index("--plane-normal") + 1])
            if "--plane-point" in argv:
                point = parse_vec(argv[argv.index("--plane-point") + 1])
            report = check_run(argv[2], normal, point)
        report["ok"] = True
        report["vtk"] = vtk.vtkVersion.GetVTKVersion()
        print(json.dumps(report))
        return 0
    except Exception as e:  # noqa: BLE001 - every failure is a failed check
        print(json.dumps({"ok": False, "error": str(e)}))
        return 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
