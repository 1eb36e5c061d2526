"""The sliding block of `pdcontact friction --case sliding` meshed by gmsh's defaults (tet4),
run through `pdcontact run`, its acceleration fitted from the frames (docs/VALIDATION.md,
"Friction").

    python3 tools/gmsh_sliding_block.py DIR [H]      # writes DIR/box.msh and DIR/s<tan>.toml
    pdcontact run -o DIR/o0.5 DIR/s0.5.toml          # (and s0.2, s1.0)
    python3 tools/gmsh_sliding_block.py --fit DIR/o0.5 0.5

The block is 0.1 x 0.1 x 0.05 m (E = 0.1 GPa, nu = 1/4, rho = 1000 kg/m3) on a rigid plane,
gravity turned by theta, mu = 0.3, explicit for 0.1 s; it starts sunk by the penalty's
penetration at rest (R = Delta/2, Delta from the mesh's mean volume per node). The fit is a
parabola through the volume-weighted mean x displacement over the last four fifths of the run.
"""
import argparse
import math
import re

MU, E, RHO, G = 0.3, 1e8, 1000.0, 9.81
SIZE = (0.1, 0.1, 0.05)


def write(d, h):
    import os

    import gmsh

    os.makedirs(d, exist_ok=True)
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add("box")
    gmsh.model.occ.addBox(0, 0, 0, *SIZE)
    gmsh.model.occ.synchronize()
    gmsh.model.addPhysicalGroup(3, [1], name="block")
    gmsh.option.setNumber("Mesh.MeshSizeMax", h)
    gmsh.model.mesh.generate(3)
    gmsh.write(os.path.join(d, "box.msh"))
    x = gmsh.model.mesh.getNodes()[1].reshape(-1, 3)
    gmsh.finalize()
    nodes, bottom = len(x), int((abs(x[:, 2]) < 1e-9).sum())
    volume = SIZE[0] * SIZE[1] * SIZE[2]
    m = RHO * volume
    k = 4.0 / (3.0 * (1 - 0.0625) / E) * math.sqrt(0.5 * (volume / nodes) ** (1 / 3))
    for slope in (0.2, 0.5, 1.0):
        t = math.atan(slope)
        sink = (m * G * math.cos(t) / bottom / k) ** (2 / 3)
        with open(os.path.join(d, f"s{slope}.toml"), "w") as f:
            f.write(f'''# tools/gmsh_sliding_block.py: tan theta = {slope}, mu = {MU}
[solver]
kind = "explicit"
end_time = 0.1
[output]
every = 200
[[body]]
name = "block"
mesh = "box.msh"
translate = [0.0, 0.0, -{sink:e}]
kinematics = "small"
[body.material]
youngs_modulus = {E:e}
poisson_ratio = 0.25
density = {RHO}
[[body]]
name = "plane"
kind = "rigid"
generator = {{ shape = "plane", point = [0.05, 0.05, 0.0], normal = [0.0, 0.0, 1.0], size = 4.0, divisions = 1 }}
[[contact]]
slave = "block"
master = "plane"
friction = {MU}
[[load]]
body = "block"
force = [{m * G * math.sin(t):e}, 0.0, {-m * G * math.cos(t):e}]
''')
    print(f"{nodes} nodes, {bottom} on the bottom face")


def fit(out, slope):
    import numpy as np
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy

    ts, xs = [], []
    pvd = open(f"{out}/run.pvd").read()
    for t, f in re.findall(r'timestep="([^"]+)"[^>]*file="([^"]+)"', pvd):
        r = vtk.vtkXMLUnstructuredGridReader()
        r.SetFileName(f"{out}/{f[:-4]}/block_particles.vtu")
        r.Update()
        p = r.GetOutput().GetPointData()
        u = vtk_to_numpy(p.GetArray("displacement"))
        v = vtk_to_numpy(p.GetArray("volume"))
        ts.append(float(t))
        xs.append((u[:, 0] * v).sum() / v.sum())
    ts, xs = np.array(ts), np.array(xs)
    k = ts >= 0.2 * ts[-1]
    a = np.linalg.lstsq(np.vstack([np.ones(k.sum()), ts[k], 0.5 * ts[k] ** 2]).T, xs[k], rcond=None)[0][2]
    th = math.atan(slope)
    theory = max(0.0, G * (math.sin(th) - MU * math.cos(th)))
    scale = theory if theory > 0 else G * math.sin(th)
    print(f"tan theta = {slope}: acceleration {a:.5f} m/s2 against {theory:.5f}, "
          f"{100 * (a - theory) / scale:+.3f} %; travelled {xs[-1]:.3e} m")


ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
ap.add_argument("dir")
ap.add_argument("value", nargs="?", type=float)
ap.add_argument("--fit", action="store_true", help="DIR is a run's output; VALUE its tan theta")
args = ap.parse_args()
if args.fit:
    fit(args.dir, args.value)
else:
    write(args.dir, args.value or 0.01)
