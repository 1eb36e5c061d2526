#!/usr/bin/env bash
# pdcontact's LPS force pass (model = "lps") against LAMMPS's pair_style peri/lps, and against
# pdcontact's own bond-based pass on the same body.
#
#   tools/peer_lammps_lps.sh [DX] [STEPS] [RUNS] [NU] [PD_DX]   (defaults 0.04 200 3 0.3 DX)
#
# LAMMPS: a sphere (R = 1 m) of simple cubic lattice points of spacing DX, peri/lps with
# K and G from E = 1 GPa and NU, horizon 3.0002 DX, no bond breaks, velocity Verlet, STEPS
# steps from a uniform expansion (v = 0.1 x): its loop time per step. pdcontact: the built-in
# sphere (R = 1 m, surface spacing PD_DX, hex8 cubed sphere: not a lattice; PD_DX = 1.4 DX
# gives about as many particles), finite kinematics, `bench --adr` (the bare force pass of the body,
# timed STEPS times), once as the LPS and once bond-based. The figure compared is bond
# updates per second: directed bonds x passes / seconds. Prints a table; installs Debian's
# lammps package if no LAMMPS binary is found (needs root or sudo).
set -euo pipefail

DX=${1:-0.04}
STEPS=${2:-200}
RUNS=${3:-3}
NU=${4:-0.3}
PD_DX=${5:-$DX}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT

. "$ROOT/tools/peer_lammps_common.sh"
LMP=$(lammps_binary)
MPIRUN=$(command -v mpirun || true)

read -r K G < <(python3 -c "e=1e9; nu=$NU; print(e/(3*(1-2*nu)), e/(2*(1+nu)))")

cat >"$WORK/in.sphere" <<EOF
# pdcontact peer problem: LPS sphere of lattice points, uniform expansion, no bond breaks
units           si
boundary        s s s
atom_style      peri
atom_modify     map array
variable        dx equal ${DX}
variable        delta equal 3.0002*\${dx}
lattice         sc \${dx}
region          ball sphere 0 0 0 1.0 units box
create_box      1 ball
create_atoms    1 region ball
set             group all density 1000.0
set             group all volume \$(v_dx^3)
# K, G, horizon, s00 = 1 (no bond breaks within the run), alpha = 0
pair_style      peri/lps
pair_coeff      * * ${K} ${G} \${delta} 1.0 0.0
neighbor        0.0001 bin
variable        vx atom 0.1*x
variable        vy atom 0.1*y
variable        vz atom 0.1*z
velocity        all set v_vx v_vy v_vz
thermo          ${STEPS}
fix             1 all nve
timestep        1.0e-5
run             ${STEPS}
EOF

scene() {
    cat <<EOF
[solver]
kind = "adr"
[[body]]
name = "ball"
generator = { shape = "sphere", radius = 1.0, spacing = ${PD_DX} }
kinematics = "finite"
[body.material]
youngs_modulus = 1e9
poisson_ratio = $1
density = 1000.0
model = "$2"
[[body]]
name = "floor"
kind = "rigid"
generator = { shape = "plane", point = [0.0, 0.0, -1.0], normal = [0.0, 0.0, 1.0], size = 4.0 }
[[contact]]
slave = "ball"
master = "floor"
[[load]]
body = "ball"
force = [0.0, 0.0, -1e6]
EOF
}
scene "$NU" lps >"$WORK/lps.toml"
scene 0.25 bond-based >"$WORK/bond.toml"

echo "building pdcontact (release)" >&2
(cd "$ROOT" && cargo build --release --quiet)
PD="${CARGO_TARGET_DIR:-$ROOT/target}/release/pdcontact"


# LAMMPS: "bond_updates_per_second atoms neighbours_per_atom".
lammps_once() {
    local log="$WORK/log.lammps"
    (cd "$WORK" && "$@" -in in.sphere -log "$log" >/dev/null)
    awk -v s="$STEPS" '/^Loop time of/ {t=$4; n=$(NF-1)}
         /^Total # of neighbors/ {nb=$NF}
         END {printf "%.6e %s %.2f\n", nb*s/t, n, nb/n}' "$log"
}

# pdcontact: "bond_updates_per_second particles bonds_per_particle".
pd_once() {
    "$PD" bench --adr "$WORK/$1.toml" --steps "$STEPS" --threads "$2" --json |
        python3 -c 'import json,sys; r=json.load(sys.stdin); print("%.6e" % (r["bonds"] / r["bond_pass_seconds"]), r["particles"], "%.2f" % (r["bonds"] / r["particles"]))'
}

declare -A RATE COUNT PARTNERS
measure() {
    local key=$1; shift
    local rates=() line
    for _ in $(seq "$RUNS"); do
        line=$("$@")
        echo "  $key: $line" >&2
        rates+=("$(echo "$line" | cut -d' ' -f1)")
        COUNT[$key]=$(echo "$line" | cut -d' ' -f2)
        PARTNERS[$key]=$(echo "$line" | cut -d' ' -f3)
    done
    RATE[$key]=$(printf '%s\n' "${rates[@]}" | median)
}

measure lammps_1 lammps_once "$LMP"
if [ -n "$MPIRUN" ]; then
    measure lammps_2 lammps_once "$MPIRUN" --allow-run-as-root --oversubscribe -np 2 "$LMP"
fi
for t in 1 2; do
    measure "lps_$t" pd_once lps "$t"
    measure "bond_$t" pd_once bond "$t"
done

echo
echo "DX = $DX (pdcontact $PD_DX), nu = $NU, $STEPS passes, median of $RUNS runs; $(head -1 "$WORK/log.lammps" 2>/dev/null || true)"
printf '| %-34s | %9s | %9s | %15s |\n' "program" particles "partners" "bond updates/s"
printf '|%s|%s|%s|%s|\n' "------------------------------------" "----------:" "----------:" "----------------:"
row() { printf '| %-34s | %9s | %9s | %15.4e |\n' "$1" "${COUNT[$2]}" "${PARTNERS[$2]}" "${RATE[$2]}"; }
row "LAMMPS peri/lps, 1 rank" lammps_1
[ -n "${RATE[lammps_2]:-}" ] && row "LAMMPS peri/lps, 2 ranks" lammps_2
row "pdcontact LPS, 1 thread" lps_1
row "pdcontact LPS, 2 threads" lps_2
row "pdcontact bond-based, 1 thread" bond_1
row "pdcontact bond-based, 2 threads" bond_2
awk -v a="${RATE[lps_1]}" -v b="${RATE[lammps_1]}" -v c="${RATE[bond_1]}" \
    'BEGIN {printf "\nLPS 1 thread / LAMMPS 1 rank = %.2fx; LPS / bond-based (1 thread) = %.2f\n", a/b, a/c}'
