#!/usr/bin/env python3
"""Benchmark of the Gmsh MSH importer against gmsh's own reader.

Generates (with the gmsh Python API) a structured hex8 box of 99 x 99 x 99 elements, i.e.
100^3 = 1,000,000 nodes, saved as MSH 4.1 ASCII in a temporary directory (never in the repo).
Then it times, each in a fresh process and taking the median of 3 runs:

* gmsh's reader: `gmsh.initialize(); t = time.perf_counter(); gmsh.open(f); ...`
  (`gmsh` from PyPI, 4.15.2 was used), peak RSS from `resource.getrusage`;
* our reader: the `read_mesh` example of `pdcontact-importers` (release build), which reports
  its own time (file read from disk included) and peak RSS (VmHWM).

and prints a markdown table: file size, reader, seconds, MB/s, peak RSS, ratio to gmsh.

    python3 tools/bench_msh_import.py [--cells 99] [--runs 3] [--keep DIR] [--binary PATH]

1 MB = 10^6 bytes throughout.
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

GENERATE = r"""
import sys, gmsh
n, out = int(sys.argv[1]), sys.argv[2]
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.model.add("box")
gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
gmsh.model.occ.synchronize()
for _, c in gmsh.model.getEntities(1):
    gmsh.model.mesh.setTransfiniteCurve(c, n + 1)
for _, s in gmsh.model.getEntities(2):
    gmsh.model.mesh.setTransfiniteSurface(s)
    gmsh.model.mesh.setRecombine(2, s)
gmsh.model.mesh.setTransfiniteVolume(1)
gmsh.model.mesh.setRecombine(3, 1)
gmsh.model.mesh.generate(3)
gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
gmsh.option.setNumber("Mesh.Binary", 0)
gmsh.write(out)
gmsh.finalize()
"""

GMSH_READ = r"""
import json, resource, sys, time, gmsh
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
t = time.perf_counter()
gmsh.open(sys.argv[1])
seconds = time.perf_counter() - t
rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
nodes = len(gmsh.model.mesh.getNodes()[0])
print(json.dumps({"seconds": seconds, "nodes": nodes, "peak_rss_mb": rss / 1e6}))
gmsh.finalize()
"""


def run_json(cmd):
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def median_of(cmd, runs):
    results = [run_json(cmd) for _ in range(runs)]
    return (
        statistics.median(r["seconds"] for r in results),
        statistics.median(r["peak_rss_mb"] for r in results),
        results[0],
    )


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cells", type=int, default=99, help="elements per box edge (99: 1M nodes)")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--keep", help="directory for the generated file (default: a temp dir)")
    ap.add_argument("--binary", help="read_mesh binary (default: build it with cargo)")
    args = ap.parse_args()

    binary = args.binary
    if binary is None:
        target = os.environ.get("CARGO_TARGET_DIR", os.path.join(REPO, "target"))
        subprocess.run(
            ["cargo", "build", "--release", "-p", "pdcontact-importers", "--example", "read_mesh"],
            cwd=REPO,
            check=True,
        )
        binary = os.path.join(target, "release", "examples", "read_mesh")

    with tempfile.TemporaryDirectory() as tmp:
        folder = args.keep or tmp
        path = os.path.join(folder, f"box_hex8_{args.cells}.msh")
        if not os.path.exists(path):
            print(f"generating {path} ...", file=sys.stderr)
            subprocess.run([sys.executable, "-c", GENERATE, str(args.cells), path], check=True)
        size_mb = os.path.getsize(path) / 1e6

        g_s, g_rss, g_first = median_of([sys.executable, "-c", GMSH_READ, path], args.runs)
        o_s, o_rss, o_first = median_of([binary, path], args.runs)
        if g_first["nodes"] != o_first["nodes"]:
            sys.exit(f"node counts differ: gmsh {g_first['nodes']}, ours {o_first['nodes']}")

        print(f"{o_first['nodes']} nodes, {o_first['elements']} elements "
              f"({o_first['solids']} hex8), median of {args.runs} runs\n")
        print("| file size (MB) | reader | seconds | MB/s | peak RSS (MB) | speed vs gmsh |")
        print("|---:|---|---:|---:|---:|---:|")
        print(f"| {size_mb:.1f} | gmsh.open (gmsh 4.15.2 Python API) | {g_s:.3f} | "
              f"{size_mb / g_s:.1f} | {g_rss:.0f} | 1.0x |")
        print(f"| {size_mb:.1f} | pdcontact-importers `msh::read` | {o_s:.3f} | "
              f"{size_mb / o_s:.1f} | {o_rss:.0f} | {g_s / o_s:.1f}x |")
        print(f"\npeak RSS of our reader: {o_rss / size_mb:.2f}x the file size")


if __name__ == "__main__":
    main()
