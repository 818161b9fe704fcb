#!/usr/bin/env bash
# Installs what spam-ark needs on Debian 12 (run as root). Safe to run again.
set -euo pipefail
export DEBIAN_FRONTEND=noninteractive
packages=(build-essential cmake pkg-config libsundials-dev petsc-dev libhdf5-openmpi-dev hdf5-tools
          openmpi-bin python3 python3-matplotlib python3-numpy)
# openmpi-bin: mpiexec for multi-rank runs and their tests (petsc-dev pulls it in through
# libopenmpi-dev today; named here because the tests call it).
# gcc's sanitizer runtimes for tools/sanitize.sh (libasan8, libubsan1) come with gcc-12
# (libgcc-12-dev depends on them): nothing more to install.
# Optional, each large: --bench adds the benchmarks' peers, LAMMPS and PySPH (no test needs
# them); --paraview adds ParaView with its Python (pvpython) and a virtual X server, for
# tests/run_paraview.py (which skips without them).
for flag in "$@"; do
  case "$flag" in
    --bench) packages+=(lammps time python3-pysph) ;;
    --paraview) packages+=(paraview python3-paraview xvfb xauth) ;;
    *) echo "tools/deps.sh: unknown flag $flag (accepted: --bench, --paraview)" >&2; exit 2 ;;
  esac
done
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  apt-get update -qq
  apt-get install -y -qq "${missing[@]}"
fi
