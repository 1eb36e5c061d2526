#!/usr/bin/env bash
# Regenerates every stored mesh in meshes/ from its committed .geo source, then
# checks them with tools/check_meshes.py.
#
#   tools/regenerate_meshes.sh              # all meshes, then the check
#   tools/regenerate_meshes.sh --no-check   # skip the check (it needs meshio, numpy)
#   tools/regenerate_meshes.sh sphere_r1_d008 block_hex   # only these
#
# Needs the gmsh Python package (the PyPI wheel bundles the gmsh library):
#   python3 -m pip install gmsh==4.15.2
# The meshes are deterministic for a given gmsh version (transfinite meshes
# are exact; the tet mesh uses one thread); they were made with 4.15.2, and
# another version warns and may write different (equally valid) tet meshes.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(dirname "$here")"
meshes="$root/meshes"
py="${PYTHON:-python3}"
expected_version="4.15.2"

# Stored meshes: .geo source -> .msh (same base name).
all=(sphere_r1_d008 sphere_r1_d012 sphere_r1_d006 block_hex sphere_tet4 sphere_tet4_h007 cylinder_tet4_h006 sphere_hex_h020 sphere_cap_quarter sphere_cap_quarter_tet4 sphere_tet10_h008 sphere_tet4_graded sphere_hex20_h030 roller_hex_extruded bar_tet4_h005 beam_slot_tet4_h002 two_boxes_gap inclined_block_tet4_h005 inclined_block_hex_h012 inclined_block_tet10_h012 inclined_block_tet4_h007 block_graded_tet4_h002)

check=1
names=()
for arg in "$@"; do
    case "$arg" in
        --no-check) check=0 ;;
        -h|--help) sed -n '2,13p' "$0"; exit 0 ;;
        -*) echo "unknown option: $arg" >&2; exit 2 ;;
        *) names+=("${arg%.*}") ;;
    esac
done
[ ${#names[@]} -eq 0 ] && names=("${all[@]}")

if ! version="$("$py" -c 'import gmsh; print(gmsh.__version__)' 2>/dev/null)"; then
    echo "error: the gmsh Python package is missing: $py -m pip install gmsh==$expected_version" >&2
    exit 1
fi
if [ "$version" != "$expected_version" ]; then
    echo "warning: gmsh $version found, the stored meshes were made with $expected_version" >&2
fi
echo "gmsh $version"

tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

for name in "${names[@]}"; do
    geo="$meshes/$name.geo"
    if [ ! -f "$geo" ]; then
        echo "error: no $geo" >&2
        exit 1
    fi
    # One Python process per mesh, so that no option leaks from one to the next.
    "$py" - "$geo" "$tmp/$name.msh" <<'PY'
import sys
import gmsh

geo, out = sys.argv[1], sys.argv[2]
gmsh.initialize(["gmsh", "-v", "2"])  # warnings and errors only
gmsh.open(geo)                        # options (MSH 4.1 ASCII, SaveAll = 0) come from the .geo
gmsh.model.mesh.generate(3)
gmsh.write(out)
gmsh.finalize()
PY
    mv "$tmp/$name.msh" "$meshes/$name.msh"
    "$py" -c 'import hashlib, os, sys; p = sys.argv[1]
print("%-20s %9d bytes  sha256 %s" % (os.path.basename(p), os.path.getsize(p),
      hashlib.sha256(open(p, "rb").read()).hexdigest()[:16]))' "$meshes/$name.msh"
done

if [ "$check" = 1 ]; then
    if "$py" -c 'import meshio, numpy' 2>/dev/null; then
        files=()
        for name in "${names[@]}"; do files+=("$meshes/$name.msh"); done
        "$py" "$here/check_meshes.py" "${files[@]}"
    else
        echo "meshio/numpy missing: skipped tools/check_meshes.py ($py -m pip install meshio numpy)" >&2
    fi
fi
