# Shared by tools/peer_lammps.sh and tools/peer_lammps_lps.sh (sourced, not run).

# Prints the path of a LAMMPS binary; installs Debian's lammps package first if there is none
# (needs root or sudo).
lammps_binary() {
    local name
    for name in lmp lmp_serial lmp_mpi lammps; do
        if command -v "$name" >/dev/null 2>&1; then
            command -v "$name"
            return 0
        fi
    done
    echo "LAMMPS not found: installing Debian's lammps package" >&2
    local sudo=""
    if [ "$(id -u)" != 0 ]; then sudo=sudo; fi
    $sudo apt-get update -qq >&2
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq lammps >&2
    command -v lmp || { echo "error: lammps installed but no lmp binary found" >&2; return 2; }
}

# The median of the numbers on stdin, one a line.
median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
