#!/bin/bash
# Converts each mesh given (default: the corpus and the stored spheres and cylinder) with
# `pdcontact convert`, then runs its case as written by both quasi-static solvers, ADR and the
# static one, and prints a line per run: particles, converged, iterations, wall, contact radius
# and peak pressure (docs/PERFORMANCE.md, "The cases `convert` writes").
#   tools/convert_solvers.sh [MESH ...]      # PDCONTACT=path/to/pdcontact, OUT=folder
set -u
root=$(cd "$(dirname "$0")/.." && pwd)
P=${PDCONTACT:-$root/target/release/pdcontact}
out=${OUT:-$(mktemp -d)}
if [ $# -eq 0 ]; then
  set -- "$root"/../shared/corpus/*/*.cdb "$root"/../shared/corpus/*/*.inp \
    "$root"/../shared/corpus/*/*.msh "$root"/meshes/sphere_tet4_h007.msh \
    "$root"/meshes/sphere_hex_h020.msh "$root"/meshes/sphere_tet10_h008.msh \
    "$root"/meshes/cylinder_tet4_h006.msh
fi
for f in "$@"; do
  b=$(basename "$f"); d=$out/$b
  rm -rf "$d"
  if ! "$P" convert "$f" -o "$d" --quiet > /dev/null 2>&1; then echo "$b: convert refused it"; continue; fi
  for k in adr static; do
    # The first `kind` is the solver's (the bodies' come after it).
    sed "0,/^kind = /s/^kind = .*/kind = \"$k\"/; /^max_iterations = /d" \
      "$d/case.toml" > "$d/$k.toml"
    timeout 300 "$P" run "$d/$k.toml" -o "$d/out_$k" --json --quiet > "$d/$k.json" 2> "$d/$k.err"
    python3 - "$d/$k.json" "$b" "$k" <<'PY'
import json, sys
path, mesh, kind = sys.argv[1:]
try:
    d = json.load(open(path))
except ValueError:
    print(f"{mesh} {kind}: no summary (see {path[:-5]}.err)")
    sys.exit()
print(f"{mesh} {kind}: particles {d['particles']}, converged {d['converged']}, "
      f"iterations {d['iterations']}, wall {d['wall_seconds']:.2f} s, "
      f"radius {d['contact_radius']}, peak {d['peak_pressure']}")
PY
  done
done
