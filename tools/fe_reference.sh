#!/usr/bin/env bash
# Finite-element reference for the sphere-on-plane scene: CalculiX (ccx) with
# face-to-face penalty contact against a rigid plane, compared with Hertz by the
# project's three figures (MRE within 0.8a, fitted contact radius, force balance).
# See docs/FE_REFERENCE.md.
#
#   tools/fe_reference.sh                      # the five cases (the last takes minutes)
#   tools/fe_reference.sh --quick              # without the 3D case h = a/20
#   tools/fe_reference.sh --json out/fe_reference.json
#   tools/fe_reference.sh --case c3d10-quarter:0.1 --profiles
#   tools/fe_reference.sh --help               # every option
#
# Installs calculix-ccx with apt-get when ccx is missing, and gmsh/numpy with pip when
# python3 cannot import them. CalculiX runs in a temporary directory (removed at the
# end; --workdir DIR keeps its files), never in the repository.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
py="${PYTHON:-python3}"

for arg in "$@"; do
    case "$arg" in
        -h|--help) sed -n '2,15p' "$0"; echo; PYTHONPATH="$here" "$py" -m fe_reference --help; exit 0 ;;
    esac
done

as_root() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }

if ! command -v ccx >/dev/null 2>&1; then
    echo "ccx not found: installing calculix-ccx" >&2
    if ! as_root apt-get install -y calculix-ccx >&2; then
        as_root apt-get update >&2
        as_root apt-get install -y calculix-ccx >&2
    fi
fi

if ! "$py" -c "import gmsh, numpy" >/dev/null 2>&1; then
    echo "installing gmsh and numpy for $py" >&2
    "$py" -m pip install gmsh==4.15.2 numpy >&2
fi

export PYTHONDONTWRITEBYTECODE=1
export PYTHONPATH="$here${PYTHONPATH:+:$PYTHONPATH}"
exec "$py" -m fe_reference "$@"
