"""Running ccx and reading its .dat file."""
import os
import re
import shutil
import subprocess
import time

_BLOCK = re.compile(r"^\s*(displacements|forces|total force)\s*\(\S+\)\s*for set\s+(\S+)\s+and time\s+(\S+)")


def run(job, workdir, threads=2):
    """Runs ``ccx -i job`` in workdir; returns wall seconds. Raises on failure."""
    exe = shutil.which("ccx")
    if exe is None:
        raise RuntimeError("ccx not found (apt-get install -y calculix-ccx)")
    env = dict(os.environ)
    for k in ("OMP_NUM_THREADS", "CCX_NPROC_EQUATION_SOLVER", "CCX_NPROC_STIFFNESS",
              "CCX_NPROC_RESULTS"):
        env[k] = str(threads)
    t = time.perf_counter()
    with open(os.path.join(workdir, job + ".log"), "w") as log:
        rc = subprocess.call([exe, "-i", job], cwd=workdir, stdout=log, stderr=subprocess.STDOUT,
                             env=env)
    seconds = time.perf_counter() - t
    text = open(os.path.join(workdir, job + ".log"), errors="replace").read()
    if rc != 0 or "*ERROR" in text or "Job finished" not in text:
        tail = "\n".join(text.splitlines()[-25:])
        raise RuntimeError(f"ccx {job} failed (exit {rc}):\n{tail}")
    return seconds


def read_dat(path):
    """{(kind, set): {node: (v1, v2, v3)}} of the last time in the file; a 'total force'
    block is stored under node 0."""
    blocks = {}
    current = None
    for line in open(path):
        m = _BLOCK.match(line)
        if m:
            kind, name = m.group(1), m.group(2).upper()
            current = {}
            blocks[(kind, name)] = current
            continue
        parts = line.split()
        if current is None or not parts:
            continue
        try:
            vals = [float(v) for v in parts]
        except ValueError:
            current = None
            continue
        if len(vals) == 3:
            current[0] = tuple(vals)
        elif len(vals) == 4:
            current[int(vals[0]) - 1] = tuple(vals[1:])
        else:
            current = None
    return blocks


def log_iterations(path):
    """Newton iterations of each increment, from ccx's log (each starts at iteration 1)."""
    numbers = [int(n) for n in re.findall(r"^\s*iteration (\d+)", open(path, errors="replace").read(), re.M)]
    counts = []
    for n in numbers:
        if n == 1:
            counts.append(0)
        if counts:
            counts[-1] += 1
    return counts
