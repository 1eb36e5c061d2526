#!/usr/bin/env python3
"""The Cattaneo-Mindlin scene of `pdcontact friction --case mindlin` meshed by gmsh's
defaults, as a user would mesh it: the sphere's shell R - 3a <= r <= R (R = 1 m) cut by the
box -3a <= x <= 3a, 0 <= y <= 3a, z <= 0 (half a cap around the south pole, its inner
spherical face the physical surface "top", where the holder grips it), and the block
-3a <= x <= 3a, 0 <= y <= 3a, -1 - 3a <= z <= -1 under it (its bottom face the physical
surface "bottom"), both halved by the symmetry plane y = 0.

    python3 tools/gmsh_mindlin.py DIR H [--a A] [--kind tet4|tet10|hex] [--seed N]

Writes DIR/sphere.msh and DIR/block.msh, each meshed with only
Mesh.MeshSizeMin = Mesh.MeshSizeMax = H (tet4 by default; tet10: second order, every node
a particle with `second_order = "all-nodes"`; hex: each tet split into four hexes,
Mesh.SubdivisionAlgorithm = 2), and prints their node counts. Then

    pdcontact friction --case mindlin --sphere-mesh DIR/sphere.msh --block-mesh DIR/block.msh

runs the push on them (A must match --contact-radius there; both default to 0.05 m).
Needs: python3 -m pip install gmsh==4.15.2
"""
import argparse
import os

import gmsh


def mesh(path, build, h, kind, seed):
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add(os.path.basename(path))
    build()
    gmsh.option.setNumber("Mesh.MeshSizeMin", h)
    gmsh.option.setNumber("Mesh.MeshSizeMax", h)
    gmsh.option.setNumber("General.NumThreads", 1)
    if seed > 1:
        gmsh.option.setNumber("Mesh.RandomSeed", seed)
        gmsh.option.setNumber("Mesh.RandomFactor", 1e-6)
    if kind == "hex":
        gmsh.option.setNumber("Mesh.SubdivisionAlgorithm", 2)
    gmsh.model.mesh.generate(3)
    if kind == "tet10":
        gmsh.model.mesh.setOrder(2)
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.option.setNumber("Mesh.Binary", 1)
    n = len(gmsh.model.mesh.getNodes(-1, -1, False, False)[0])
    gmsh.write(path)
    gmsh.finalize()
    return n


def sphere(a):
    def build():
        occ = gmsh.model.occ
        outer = occ.addSphere(0, 0, 0, 1.0)
        inner = occ.addSphere(0, 0, 0, 1.0 - 3 * a)
        shell, _ = occ.cut([(3, outer)], [(3, inner)])
        box = occ.addBox(-3 * a, 0, -1.1, 6 * a, 3 * a, 1.1)
        occ.intersect(shell, [(3, box)])
        occ.synchronize()
        volumes = [t for _, t in gmsh.model.getEntities(3)]
        gmsh.model.addPhysicalGroup(3, volumes, name="sphere")
        faces = [t for _, t in gmsh.model.getBoundary([(3, v) for v in volumes], oriented=False)]

        def radius(tag):
            x, y, z = occ.getCenterOfMass(2, tag)
            return (x * x + y * y + z * z) ** 0.5

        spheres = [t for t in faces if "Sphere" in gmsh.model.getType(2, t)]
        gmsh.model.addPhysicalGroup(2, [min(spheres, key=radius)], name="top")

    return build


def block(a):
    def build():
        occ = gmsh.model.occ
        occ.addBox(-3 * a, 0, -1 - 3 * a, 6 * a, 3 * a, 3 * a)
        occ.synchronize()
        gmsh.model.addPhysicalGroup(3, [t for _, t in gmsh.model.getEntities(3)], name="block")
        bottom = gmsh.model.getEntitiesInBoundingBox(
            -1, -1, -1 - 3 * a - 1e-6, 1, 1, -1 - 3 * a + 1e-6, 2)
        gmsh.model.addPhysicalGroup(2, [t for _, t in bottom], name="bottom")

    return build


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("dir")
    p.add_argument("h", type=float)
    p.add_argument("--a", type=float, default=0.05)
    p.add_argument("--kind", choices=["tet4", "tet10", "hex"], default="tet4")
    p.add_argument("--seed", type=int, default=1)
    o = p.parse_args()
    os.makedirs(o.dir, exist_ok=True)
    ns = mesh(os.path.join(o.dir, "sphere.msh"), sphere(o.a), o.h, o.kind, o.seed)
    nb = mesh(os.path.join(o.dir, "block.msh"), block(o.a), o.h, o.kind, o.seed)
    print(f"nodes: sphere {ns}, block {nb} ({o.kind}, H = {o.h} m, a = {o.a} m)")


if __name__ == "__main__":
    main()
