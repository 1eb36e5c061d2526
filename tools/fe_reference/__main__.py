"""python3 -m fe_reference: the CalculiX reference series (see docs/FE_REFERENCE.md)."""
import argparse
import json
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time

from .problem import Problem

# (model, h/a) in the order they run; the last one is what --quick leaves out.
SERIES = [("cax8-axisymmetric", 0.1), ("cax8-axisymmetric", 0.05),
          ("c3d10-quarter", 0.2), ("c3d10-quarter", 0.1), ("c3d10-quarter", 0.05)]
QUICK_SKIPS = {("c3d10-quarter", 0.05)}
JSON_KEYS = ("model", "h_over_a", "nodes", "mre", "radius_error", "force_balance_error",
             "wall_seconds")


def machine():
    model = platform.processor() or platform.machine()
    try:
        for line in subprocess.run(["lscpu"], capture_output=True, text=True).stdout.splitlines():
            if line.startswith("Model name:"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    return f"{model}, {os.cpu_count()} cores, load average {load:.1f} at start"


def ccx_version():
    exe = shutil.which("ccx")
    if not exe:
        return "ccx not found"
    out = subprocess.run([exe, "-v"], capture_output=True, text=True).stdout
    for line in out.splitlines():
        if "Version" in line:
            return "CalculiX " + line.split("Version", 1)[1].strip()
    return "CalculiX (version unknown)"


def parse_case(text):
    model, _, h = text.partition(":")
    if model not in ("cax8-axisymmetric", "c3d10-quarter") or not h:
        raise argparse.ArgumentTypeError("expected MODEL:H_OVER_A, e.g. c3d10-quarter:0.1")
    return model, float(h)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="fe_reference", description=__doc__)
    ap.add_argument("--quick", action="store_true", help="skip the 3D case h = a/20")
    ap.add_argument("--json", metavar="PATH", help="write fe_reference.json here")
    ap.add_argument("--case", action="append", type=parse_case, metavar="MODEL:H",
                    help="run only these cases (repeatable), e.g. cax8-axisymmetric:0.05")
    ap.add_argument("--workdir", help="keep the CalculiX files here (default: a temporary "
                    "directory, removed afterwards)")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--loading", choices=("body", "equator"), default="body")
    ap.add_argument("--pressure", choices=("lumped", "consistent"), default="lumped")
    ap.add_argument("--penalty", type=float, default=1e14, help="contact stiffness, Pa/m")
    ap.add_argument("--rematch", type=int, default=2)
    ap.add_argument("--nlgeom", action="store_true", help="finite strain (not Hertz's model)")
    ap.add_argument("--profiles", action="store_true", help="also print p(r) of each case")
    ap.add_argument("--contact-radius", type=float, default=0.15, metavar="A",
                    help="Hertz contact radius a in m (the load follows from it; default 0.15, "
                         "a/R = 0.15; `pdcontact sweep` and `validate --study` use 0.3)")
    ap.add_argument("--ball", type=float, default=0.0, metavar="RB",
                    help="press the sphere on a rigid ball of radius RB (m) in place of the "
                         "plane (Hertz with 1/R* = 1/R + 1/RB)")
    args = ap.parse_args(argv)

    from . import run  # imports gmsh: after argument parsing, so --help works without it

    t0 = time.perf_counter()
    cases = args.case or [c for c in SERIES if not (args.quick and c in QUICK_SKIPS)]
    problem = Problem(contact_radius=args.contact_radius, ball=args.ball)
    against = f"a rigid ball RB = {args.ball:g} m" if args.ball > 0 else "a rigid plane"
    print(f"sphere R = {problem.radius:g} m on {against}, E = {problem.youngs:.3g} Pa, nu = "
          f"{problem.poisson:g}; P = {problem.load:.6g} N for a = {problem.contact_radius:g} m, "
          f"p0 = {problem.p0:.6g} Pa")
    print(f"machine: {machine()}; {ccx_version()}")
    print(f"options: loading {args.loading}, pressure {args.pressure}, penalty "
          f"{args.penalty:.3g} Pa/m, rematch {args.rematch}, "
          f"{'NLGEOM' if args.nlgeom else 'small strain'}")
    print(f"{'model':<18} {'h':>6} {'nodes':>7} {'samples':>7} {'MRE':>7} {'a_fit/a-1':>9} {'balance':>8} "
          f"{'p_c/Hertz-1':>11} {'ccx s':>7} {'ccx cpu':>7} {'total s':>7}", flush=True)
    top = args.workdir or tempfile.mkdtemp(prefix="fe_reference_")
    rows = []
    try:
        for model, h in cases:
            res = run.run_case(model, h, os.path.join(top, f"{model}_h{h:g}"), problem,
                               penalty=args.penalty, pressure=args.pressure,
                               rematch=args.rematch, nlgeom=args.nlgeom,
                               loading=args.loading, threads=args.threads)
            rows.append(res)
            print(f"{model:<18} {'a/%g' % round(1 / h, 3):>6} {res['nodes']:>7} {res['samples']:>7} "
                  f"{100 * res['mre']:>6.3f}% {100 * res['radius_error']:>+8.3f}% "
                  f"{res['force_balance_error']:>8.1e} {100 * res['centre_pressure_error']:>+10.2f}% "
                  f"{res['ccx_seconds']:>7.1f} {res['ccx_cpu_seconds']:>7.1f} "
                  f"{res['wall_seconds']:>7.1f}", flush=True)
            if args.profiles:
                prof = res["profile"]
                for r, p in sorted(zip(prof["r"], prof["p"])):
                    print(f"    r/a {r / problem.contact_radius:.4f}  p/p0 {p / problem.p0:.5f}"
                          f"  Hertz {problem.pressure(r) / problem.p0:.5f}")
    finally:
        if not args.workdir:
            shutil.rmtree(top, ignore_errors=True)
    print(f"total {time.perf_counter() - t0:.1f} s (ccx {sum(r['ccx_seconds'] for r in rows):.1f} s)")
    if args.json:
        with open(args.json, "w") as f:
            json.dump([{k: r[k] for k in JSON_KEYS} for r in rows], f, indent=2)
            f.write("\n")
        print(f"wrote {args.json}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
