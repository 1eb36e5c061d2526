#!/usr/bin/env python3
"""Two gmsh-default tet4 spheres pressed together, as quarter models (docs/VALIDATION.md,
"Two deformable bodies"): R = 1 m, MeshSizeMin = MeshSizeMax = H (default 0.05), the upper
sphere centred at (0, 0, 1) and cut to x >= 0, y >= 0; the lower centred at (0, 0, -1) and
cut to x >= 0, y >= 0, z >= -1 (its equator becomes a symmetry plane). Writes upper.msh,
lower.msh and scene.toml (ADR; P/4 = 9.6e6 N on the upper sphere, Hertz a = 0.3 m for two
identical spheres, the penalty radius `run` advises) into DIR.

    python3 tools/gmsh_two_spheres.py DIR [H]
"""
import os
import sys

import gmsh

SCENE = """# Two deformable gmsh tet4 spheres, quarter models (tools/gmsh_two_spheres.py)
[solver]
kind = "adr"
tolerance = 1e-4
max_iterations = 20000
[output]
every = 1000000
[[body]]
name = "upper"
mesh = "upper.msh"
kinematics = "small"
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0
[[body]]
name = "lower"
mesh = "lower.msh"
kinematics = "small"
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0
[[load]]
body = "upper"
force = [0.0, 0.0, -9.6e6]
[[contact]]
slave = "upper"
master = "lower"
radius = 2290.0
two_pass = true
[[symmetry]]
body = "upper"
axis = "x"
[[symmetry]]
body = "upper"
axis = "y"
[[symmetry]]
body = "lower"
axis = "x"
[[symmetry]]
body = "lower"
axis = "y"
[[symmetry]]
body = "lower"
axis = "z"
at = -1.0
keep = "positive"
"""


def sphere_part(path, cz, eighth, h):
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add(os.path.basename(path))
    s = gmsh.model.occ.addSphere(0, 0, cz, 1.0)
    zmin = cz if eighth else cz - 1.5
    box = gmsh.model.occ.addBox(0, 0, zmin, 2, 2, cz + 1.5 - zmin)
    gmsh.model.occ.intersect([(3, s)], [(3, box)])
    gmsh.model.occ.synchronize()
    gmsh.option.setNumber("Mesh.MeshSizeMin", h)
    gmsh.option.setNumber("Mesh.MeshSizeMax", h)
    gmsh.model.mesh.generate(3)
    gmsh.write(path)
    gmsh.finalize()


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    h = float(sys.argv[2]) if len(sys.argv) > 2 else 0.05
    os.makedirs(out, exist_ok=True)
    sphere_part(os.path.join(out, "upper.msh"), 1.0, False, h)
    sphere_part(os.path.join(out, "lower.msh"), -1.0, True, h)
    with open(os.path.join(out, "scene.toml"), "w") as f:
        f.write(SCENE)


if __name__ == "__main__":
    main()
