#!/usr/bin/env bash
# pdcontact's bond kernel against LAMMPS's pair_style peri/pmb on the same problem: a sphere
# (R = 1 m) of simple cubic lattice points of spacing DX, E = 1 GPa, rho = 1000 kg/m^3,
# horizon 3.0002 DX, v = 0.1 x, velocity Verlet with dt = 1e-5 s, 200 steps, no bond breaks.
#
#   tools/peer_lammps.sh [DX] [STEPS] [RUNS]      (defaults 0.04 200 3)
#
# Installs Debian's lammps package if no LAMMPS binary is found (needs root or sudo), builds
# pdcontact in release mode, runs each of: LAMMPS on 1 rank, LAMMPS on 2 MPI ranks (when mpirun
# is installed), pdcontact bench with 1 and 2 threads (alternating), RUNS times, and prints the median loop
# times, the throughputs (directed bonds x steps / loop seconds) and their ratios. Fails when
# the particle or partner counts of the two programs differ.
set -euo pipefail

DX=${1:-0.04}
STEPS=${2:-200}
RUNS=${3:-3}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT

. "$ROOT/tools/peer_lammps_common.sh"
LMP=$(lammps_binary)
MPIRUN=$(command -v mpirun || true)

cat >"$WORK/in.sphere" <<EOF
# pdcontact peer problem: PMB sphere of lattice points, uniform expansion, no bond breaks
units           si
boundary        s s s
atom_style      peri
atom_modify     map array
variable        dx equal ${DX}
variable        delta equal 3.0002*\${dx}
variable        c equal 12.0*1.0e9/(PI*\${delta}^4)
lattice         sc \${dx}
region          ball sphere 0 0 0 1.0 units box
create_box      1 ball
create_atoms    1 region ball
set             group all density 1000.0
set             group all volume \$(v_dx^3)
# c, horizon, s00 = 1 (no bond breaks within the run), alpha = 0
pair_style      peri/pmb
pair_coeff      * * \${c} \${delta} 1.0 0.0
neighbor        0.0001 bin
variable        vx atom 0.1*x
variable        vy atom 0.1*y
variable        vz atom 0.1*z
velocity        all set v_vx v_vy v_vz
compute         ke all ke
compute         pe all pe
variable        etot equal c_ke+c_pe
thermo_style    custom step c_ke c_pe v_etot
thermo          ${STEPS}
fix             1 all nve
timestep        1.0e-5
run             ${STEPS}
EOF

echo "building pdcontact (release)" >&2
(cd "$ROOT" && cargo build --release --quiet)
PD="${CARGO_TARGET_DIR:-$ROOT/target}/release/pdcontact"


# One LAMMPS run: prints "loop_seconds atoms neighbours_per_atom energy_drift" (the drift of
# its total energy, kinetic + PMB strain, over the run).
lammps_once() {
    local log="$WORK/log.lammps"
    (cd "$WORK" && "$@" -in in.sphere -log "$log" >/dev/null)
    awk '/^ *Step / {thermo=1; next}
         /^Loop time of/ {t=$4; n=$(NF-1); thermo=0}
         thermo && $1 ~ /^[0-9]+$/ {if (e0 == "") e0=$4; e=$4}
         /^Total # of neighbors/ {nb=$NF}
         END {d=(e-e0)/e0; if (d<0) d=-d; printf "%s %s %.4f %.3e\n", t, n, nb/n, d}' "$log"
    head -1 "$log" >"$WORK/version"
}

# One pdcontact run: prints "loop_seconds particles bonds_per_particle energy_drift".
pd_once() {
    "$PD" bench --lattice-sphere "$DX" --steps "$STEPS" --threads "$1" --json |
        python3 -c 'import json,sys; r=json.load(sys.stdin); print(r["loop_seconds"], r["particles"], "%.4f" % r["bonds_per_particle"], r["energy_drift"])'
}

declare -A LOOP COUNT PARTNERS DRIFT
measure() {
    local key=$1; shift
    local times=() line
    for _ in $(seq "$RUNS"); do
        line=$("$@")
        echo "  $key: $line" >&2
        times+=("$(echo "$line" | cut -d' ' -f1)")
        COUNT[$key]=$(echo "$line" | cut -d' ' -f2)
        PARTNERS[$key]=$(echo "$line" | cut -d' ' -f3)
        DRIFT[$key]=$(echo "$line" | cut -d' ' -f4)
    done
    LOOP[$key]=$(printf '%s\n' "${times[@]}" | median)
}

declare -A ALL
# As `measure`, one run, its loop time appended to ALL[key].
measure_append() {
    local key=$1; shift
    local line
    line=$("$@")
    echo "  $key: $line" >&2
    ALL[$key]="${ALL[$key]:-} $(echo "$line" | cut -d' ' -f1)"
    COUNT[$key]=$(echo "$line" | cut -d' ' -f2)
    PARTNERS[$key]=$(echo "$line" | cut -d' ' -f3)
    DRIFT[$key]=$(echo "$line" | cut -d' ' -f4)
}

measure lammps_1 lammps_once "$LMP"
echo "LAMMPS: $LMP, $(cat "$WORK/version")" >&2
if [ -n "$MPIRUN" ]; then
    measure lammps_2 lammps_once "$MPIRUN" --allow-run-as-root --oversubscribe -np 2 "$LMP"
fi
# One and two threads alternate, so that a slow spell of a shared machine weighs on both alike.
for _ in $(seq "$RUNS"); do
    RUNS=1 measure_append pd_1 pd_once 1
    RUNS=1 measure_append pd_2 pd_once 2
done
for key in pd_1 pd_2; do
    LOOP[$key]=$(echo "${ALL[$key]}" | tr ' ' '\n' | grep -v '^$' | median)
done

status=0
if [ "${COUNT[lammps_1]}" != "${COUNT[pd_1]}" ]; then
    echo "error: particles differ: LAMMPS ${COUNT[lammps_1]}, pdcontact ${COUNT[pd_1]}" >&2
    status=1
fi
if [ "${PARTNERS[lammps_1]}" != "${PARTNERS[pd_1]}" ]; then
    echo "error: partners per particle differ: LAMMPS ${PARTNERS[lammps_1]}, pdcontact ${PARTNERS[pd_1]}" >&2
    status=1
fi

bonds=$(awk -v n="${COUNT[pd_1]}" -v p="${PARTNERS[pd_1]}" 'BEGIN {printf "%.0f", n*p}')
echo
echo "DX = $DX, $STEPS steps, ${COUNT[pd_1]} particles, ${PARTNERS[pd_1]} partners per particle (directed), median of $RUNS runs"
printf '| %-22s | %12s | %16s | %10s |\n' program "loop seconds" "bond updates/s" "vs LAMMPS"
printf '|%s|%s|%s|%s|\n' "------------------------" "-------------:" "-----------------:" "-----------:"
row() {
    local name=$1 t=$2 ref=$3
    awk -v name="$name" -v t="$t" -v ref="$ref" -v b="$bonds" -v s="$STEPS" \
        'BEGIN {printf "| %-22s | %12.3f | %16.4e | %9.2fx |\n", name, t, b*s/t, ref/t}'
}
row "LAMMPS 1 rank" "${LOOP[lammps_1]}" "${LOOP[lammps_1]}"
[ -n "${LOOP[lammps_2]:-}" ] && row "LAMMPS 2 ranks" "${LOOP[lammps_2]}" "${LOOP[lammps_2]}"
row "pdcontact 1 thread" "${LOOP[pd_1]}" "${LOOP[lammps_1]}"
row "pdcontact 2 threads" "${LOOP[pd_2]}" "${LOOP[lammps_2]:-${LOOP[lammps_1]}}"
echo
echo "ratios: pdcontact 1 thread / LAMMPS 1 rank = $(awk -v a="${LOOP[lammps_1]}" -v b="${LOOP[pd_1]}" 'BEGIN {printf "%.2f", a/b}')x;" \
    "pdcontact 2 threads / LAMMPS 2 ranks = $(awk -v a="${LOOP[lammps_2]:-nan}" -v b="${LOOP[pd_2]}" 'BEGIN {printf "%.2f", a/b}')x;" \
    "pdcontact 2-thread speed-up = $(awk -v a="${LOOP[pd_1]}" -v b="${LOOP[pd_2]}" 'BEGIN {printf "%.2f", a/b}')x"
echo "relative energy drift over the run: LAMMPS ${DRIFT[lammps_1]}, pdcontact ${DRIFT[pd_1]}"
exit $status
