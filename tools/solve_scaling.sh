#!/usr/bin/env bash
# Time to solution against particle count: the Hertz sphere of `pdcontact validate --set hertz`
# (R = 1 m, a = 0.15 m, the quarter shell sector of depth 3a, R_penalty = 100, tolerance 1e-5)
# at several a/Δ, solved by ADR and by the static solver, one after the other. One JSON line per
# run on stdout: a/Δ, solver, particles, iterations, force evaluations, CG iterations, setup and
# solve seconds, peak RSS (MB), contact radius and peak pressure (Hertz: 0.15 m, 1.0186e8 Pa).
#
#   tools/solve_scaling.sh [A_OVER_DX ...]        # default: 8 12 15 20 25 32
#
# PDCONTACT names the binary (default: target/release/pdcontact); SOLVERS the solvers (default:
# "adr static"); OUT the folder for the runs (default: solve_scaling); threads: RAYON_NUM_THREADS.
set -euo pipefail
exe=${PDCONTACT:-target/release/pdcontact}
out=${OUT:-solve_scaling}
sizes=${*:-8 12 15 20 25 32}
mkdir -p "$out"
for n in $sizes; do
    for solver in ${SOLVERS:-adr static}; do
        dir=$out/a$n-$solver
        mkdir -p "$dir"
        python3 - "$n" "$solver" > "$dir/scene.toml" <<'PY'
import sys
n, solver = float(sys.argv[1]), sys.argv[2]
a, e, nu = 0.15, 1e9, 0.25
load = 4.0 * (e / (1 - nu * nu)) * a ** 3 / 3.0
print(f"""[solver]
kind = "{solver}"
tolerance = 1e-5
max_iterations = 200000

[output]
every = 1000000

[[body]]
name = "sphere"
generator = {{ shape = "sphere_cap", radius = 1.0, half_width = {3 * a:.6g}, depth = {3 * a:.6g}, spacing = {a / n} }}
kinematics = "small"
[body.material]
youngs_modulus = {e:e}
poisson_ratio = {nu}
density = 1000.0

[[body]]
name = "plane"
kind = "rigid"
generator = {{ shape = "plane", point = [0.0, 0.0, -1.0], normal = [0.0, 0.0, 1.0], size = 2.0 }}

[[load]]
body = "sphere"
set = "top"
force = [0.0, 0.0, -{load / 4:e}]

[[contact]]
slave = "sphere"
master = "plane"
radius = 100.0

[[symmetry]]
body = "sphere"
axis = "x"

[[symmetry]]
body = "sphere"
axis = "y"
""")
PY
        # Peak RSS of the run from the kernel's accounting of the finished child.
        python3 - "$exe" "$dir" "$n" "$solver" <<'PY'
import json, resource, subprocess, sys, time
exe, d, n, solver = sys.argv[1:]
t = time.time()
r = subprocess.run([exe, "run", f"{d}/scene.toml", "-o", d, "--quiet", "--json"],
                   capture_output=True, text=True)
wall = time.time() - t
if r.returncode != 0:
    print(json.dumps({"a_over_dx": float(n), "solver": solver, "error": r.stderr.strip()[-400:]}))
    sys.exit(0)
s = json.loads(r.stdout)
v = s["solver"]
rss = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
print(json.dumps({"a_over_dx": float(n), "solver": solver,
                  "particles": s.get("particles"), "iterations": v.get("iterations"),
                  "force_evaluations": v.get("force_evaluations"),
                  "linear_iterations": v.get("linear_iterations"),
                  "converged": v.get("converged"),
                  "solve_seconds": s.get("solve_seconds"), "wall_seconds": round(wall, 2),
                  "peak_rss_mb": round(rss), "contact_radius": s.get("contact_radius"),
                  "peak_pressure": s.get("peak_pressure")}), flush=True)
PY
    done
done
