#!/usr/bin/env python3
"""Whole spheres (R = 1 m) meshed by gmsh the several ways users mesh them, for
`pdcontact validate --mesh FILE [--partner copy]` (docs/VALIDATION.md, "Gmsh's other kernels
and algorithms"). Writes into DIR, each as MSH 4.1, MSH 2.2 (NAME_v22.msh) and INP:

- kernel_aXY_hHHH_oN: the sphere centred at (0.3, -0.2, 1.7) from OpenCASCADE's addSphere
  (occ) or from gmsh's built-in kernel as eight filled patches (geo); 2D algorithm X
  (6 the default, 5 Delaunay, 1 MeshAdapt) and 3D algorithm Y (1 the default Delaunay,
  4 Frontal, 10 HXT); MeshSizeMin = MeshSizeMax = H/1000 m; N = 1 tet4, 2 tet10.
- sphere_hex_aY_hHHH: OpenCASCADE's sphere at the origin, its tets split into hexes
  (Mesh.SubdivisionAlgorithm = 2), 3D algorithm Y.
- sphere_graded_hHHH: OpenCASCADE's sphere at the origin, graded towards its south pole by a
  Distance and Threshold field (H/1000 m within 0.4 m of the pole, 0.2 m beyond 1.2 m), as
  an FE user refines towards a contact.

    python3 tools/gmsh_sphere_variants.py DIR
"""
import sys

import gmsh


def start(h):
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("Mesh.MeshSizeMin", h)
    gmsh.option.setNumber("Mesh.MeshSizeMax", h)


def finish(path, order=1):
    gmsh.model.mesh.generate(3)
    if order == 2:
        gmsh.model.mesh.setOrder(2)
    gmsh.write(path + ".msh")
    gmsh.option.setNumber("Mesh.MshFileVersion", 2.2)
    gmsh.write(path + "_v22.msh")
    gmsh.write(path + ".inp")
    gmsh.finalize()
    print(path, flush=True)


def builtin_sphere(c):
    """The sphere of radius 1 about c as gmsh's built-in kernel makes it: twelve quarter
    circles through six poles, eight filled patches."""
    g = gmsh.model.geo
    centre = g.addPoint(*c)
    p = [g.addPoint(c[0] + dx, c[1] + dy, c[2] + dz)
         for dx, dy, dz in [(1, 0, 0), (0, 1, 0), (-1, 0, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]]

    def arc(a, b):
        return g.addCircleArc(p[a], centre, p[b])

    e = [arc(0, 1), arc(1, 2), arc(2, 3), arc(3, 0), arc(0, 4), arc(1, 4), arc(2, 4),
         arc(3, 4), arc(0, 5), arc(1, 5), arc(2, 5), arc(3, 5)]
    loops = [[e[0], e[5], -e[4]], [e[1], e[6], -e[5]], [e[2], e[7], -e[6]],
             [e[3], e[4], -e[7]], [e[0], e[9], -e[8]], [e[1], e[10], -e[9]],
             [e[2], e[11], -e[10]], [e[3], e[8], -e[11]]]
    surfaces = [g.addSurfaceFilling([g.addCurveLoop(l)]) for l in loops]
    g.addVolume([g.addSurfaceLoop(surfaces)])
    g.synchronize()


def main():
    out = sys.argv[1]
    centre = (0.3, -0.2, 1.7)
    for kernel in ["occ", "geo"]:
        for alg2, alg3 in [(6, 1), (5, 4), (6, 10), (1, 1)]:
            for h in [0.065, 0.08]:
                for order in [1, 2]:
                    start(h)
                    if kernel == "occ":
                        gmsh.model.occ.addSphere(*centre, 1.0)
                        gmsh.model.occ.synchronize()
                    else:
                        builtin_sphere(centre)
                    gmsh.option.setNumber("Mesh.Algorithm", alg2)
                    gmsh.option.setNumber("Mesh.Algorithm3D", alg3)
                    finish(f"{out}/{kernel}_a{alg2}{alg3}_h{round(h * 1000):03d}_o{order}", order)
    for h in [0.1, 0.12]:
        for alg3 in [1, 10]:
            start(h)
            gmsh.option.setNumber("Mesh.Algorithm3D", alg3)
            gmsh.option.setNumber("Mesh.SubdivisionAlgorithm", 2)
            gmsh.model.occ.addSphere(0, 0, 0, 1.0)
            gmsh.model.occ.synchronize()
            finish(f"{out}/sphere_hex_a{alg3}_h{round(h * 1000):03d}")
    for hmin in [0.02, 0.03]:
        start(hmin)
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.2)
        gmsh.model.occ.addSphere(0, 0, 0, 1.0)
        gmsh.model.occ.synchronize()
        poles = [t for _, t in gmsh.model.getEntities(0)
                 if abs(gmsh.model.getValue(0, t, [])[2] + 1.0) < 1e-9]
        field = gmsh.model.mesh.field
        distance = field.add("Distance")
        field.setNumbers(distance, "PointsList", poles)
        threshold = field.add("Threshold")
        field.setNumber(threshold, "InField", distance)
        field.setNumber(threshold, "SizeMin", hmin)
        field.setNumber(threshold, "SizeMax", 0.2)
        field.setNumber(threshold, "DistMin", 0.4)
        field.setNumber(threshold, "DistMax", 1.2)
        field.setAsBackgroundMesh(threshold)
        for key in ["MeshSizeFromPoints", "MeshSizeFromCurvature", "MeshSizeExtendFromBoundary"]:
            gmsh.option.setNumber("Mesh." + key, 0)
        finish(f"{out}/sphere_graded_h{round(hmin * 1000):03d}")


if __name__ == "__main__":
    main()
