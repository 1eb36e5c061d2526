#!/usr/bin/env python3
"""Check pdcontact's VTK output with VTK's own readers (not with the writer that made it).

    python3 tools/check_vtk.py case DIR            # a `pdcontact convert` folder
    python3 tools/check_vtk.py run DIR [--plane-normal 0,0,1] [--plane-point 0,0,-1]

`case`: particles.vtu and segments.vtu load with vtkXMLUnstructuredGridReader and hold the
fields `convert` documents.

`run`: run.pvd is parsed with VTK's XML parser (vtkXMLDataParser; plain VTK has no .pvd
reader, ParaView's pvpython does and is used when present), every file it lists loads, the last
particles frame holds every documented field, and `contact_pressure` is positive only on
particles that face the rigid plane (outward normal against the plane normal) and sit within a
spacing of it.

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


def check_run(folder, normal, point):
    pvd = os.path.join(folder, "run.pvd")
    entries = pvd_entries(pvd)
    for _, _, f in entries:
        read_vtu(os.path.join(folder, f))
    frames = [e for e in entries if e[1] == 0]
    last = frames[-1][2]
    g = read_vtu(os.path.join(folder, last))
    pd = g.GetPointData()
    require(fields(pd), {"displacement": 3, "velocity": 3, "force": 3, "contact_force": 3,
                         "contact_pressure": 1, "surface": 1, "normal": 3, "body": 1}, last)
    pressure = vtk_to_numpy(pd.GetArray("contact_pressure"))
    nrm = vtk_to_numpy(pd.GetArray("normal"))
    pos = vtk_to_numpy(g.GetPoints().GetData())
    loaded = pressure > 0
    report = {"pvd_entries": len(entries), "frames": len(frames), "last": last,
              "particles": int(g.GetNumberOfPoints()), "loaded": int(loaded.sum())}
    if normal is not None:
        n = np.array(normal, float)
        n /= np.linalg.norm(n)
        facing = nrm @ n < -0.5
        bad = loaded & ~facing
        report["loaded_not_facing"] = int(bad.sum())
        if point is not None:
            height = (pos - np.array(point, float)) @ n
            report["max_height_of_loaded"] = float(height[loaded].max()) if loaded.any() else 0.0
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
    if len(argv) < 3 or argv[1] not in ("case", "run"):
        print(__doc__)
        return 2
    try:
        if argv[1] == "case":
            report = check_case(argv[2])
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
