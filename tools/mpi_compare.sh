#!/usr/bin/env bash
# One scene on 1 and 2 threads and on 2, 3 and 4 MPI ranks (one thread each): the figures of
# summary.json with all 17 digits, the solver's milliseconds per iteration, each process's
# peak memory (and on ranks the share of the model's bonds each holds), and whether each
# decomposed run's frames equal the 1-thread frames bit for bit (tools/check_vtk.py same,
# with Python's vtk). A scene whose `max_iterations` stops it short still reports (memory
# is measured so on a model too large to solve here).
#
#   tools/mpi_compare.sh SCENE [OUT]      # OUT: folder for the runs (default: mpi_compare)
#
# PDCONTACT names the binary (default: target/release/pdcontact-mpi, `cargo build --release -p pdcontact-mpi`);
# RUNS the runs (default: "t1 t2 n2 n3 n4": tN threads, nN ranks).
set -euo pipefail
scene=$1
out=${2:-mpi_compare}
exe=${PDCONTACT:-target/release/pdcontact-mpi}
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out"
# Open MPI refuses to start as root without these (containers).
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
for run in ${RUNS:-t1 t2 n2 n3 n4}; do
    dir=$out/$run
    rm -rf "$dir"
    case $run in
        t*) RAYON_NUM_THREADS=${run#t} "$exe" run "$scene" -o "$dir" --quiet >/dev/null || true ;;
        n*) RAYON_NUM_THREADS=1 mpirun --oversubscribe -n "${run#n}" "$exe" run "$scene" -o "$dir" --quiet >/dev/null 2>&1 || true ;;
    esac
    python3 - "$run" "$dir/summary.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[2])); v = s["solver"]
print(f"{sys.argv[1]:4} iterations {v['iterations']} radius {s['contact_radius']!r} "
      f"peak {s['peak_pressure']!r} force {s['total_contact_force'][2]!r} "
      f"drift {v.get('energy_drift')!r} ms/iteration {1000 * s['solve_seconds'] / max(1, v['iterations']):.3f}")
d = s.get("decomposition")
if d:
    held = [f"{100 * b / d['model_bonds']:.1f}" for b in d["bonds"]]
    print(f"     peak MB per rank {[round(m) for m in d['peak_memory_mb'] if m]}, "
          f"bonds held % {held}, ghosts {d['ghosts']}")
else:
    print(f"     peak MB {s.get('peak_memory_mb')!r}, bonds {s['bonds']}")
PY
    case $run in
        n*) if python3 -c "import vtk" 2>/dev/null && [ -d "$out/t1" ]; then
                python3 "$here/check_vtk.py" same "$out/t1" "$dir"
            fi ;;
    esac
done
