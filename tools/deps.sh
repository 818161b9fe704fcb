#!/usr/bin/env bash
# Installs what spam-ark needs on Debian 12 (run as root). Safe to run again.
set -euo pipefail
export DEBIAN_FRONTEND=noninteractive
packages=(build-essential cmake pkg-config libsundials-dev petsc-dev libhdf5-openmpi-dev hdf5-tools
          python3 python3-matplotlib python3-numpy)
# gcc's sanitizer runtimes for tools/sanitize.sh (libasan8, libubsan1) come with gcc-12
# (libgcc-12-dev depends on them): nothing more to install.
# The benchmark's peer; only with --bench (it is large and no test needs it).
if [[ "${1:-}" == "--bench" ]]; then packages+=(lammps time); fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  apt-get update -qq
  apt-get install -y -qq "${missing[@]}"
fi
