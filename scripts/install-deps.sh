#!/usr/bin/env bash
# Installs every package pfill needs to build, test and run, from Debian 12's
# archive. Runs as root (CI) or through sudo. Skips the install when all
# packages are already present, so the README commands stay fast on re-runs.
set -euo pipefail

PACKAGES=(
  cmake g++ make pkg-config
  ocl-icd-opencl-dev opencl-headers opencl-clhpp-headers pocl-opencl-icd clinfo
  libembree-dev libtbb-dev
  libtinygltf-dev libstb-dev nlohmann-json3-dev
  libassimp-dev
  libcli11-dev doctest-dev
  oclgrind
  pybind11-dev python3-dev python3-numpy python3-pytest
  liblammps-dev libopenmpi-dev openmpi-bin  # the LAMMPS engine (--engine lammps; optional in the build)
  lammps  # lmp: Debian's LAMMPS CMake package names /usr/bin/lmp, and the read_data client test runs it
)

# The Khronos glTF validator (an npm package) checks our GLB files in the
# tests; without npm or the registry the test skips, so failure is not fatal.
install_gltf_validator() {
  local root
  root="$(cd "$(dirname "$0")/.." && pwd)/.tools"
  [ -d "$root/node_modules/gltf-validator" ] && return 0
  command -v npm >/dev/null 2>&1 || return 0
  mkdir -p "$root"
  npm install --silent --no-audit --no-fund --prefix "$root" gltf-validator >/dev/null 2>&1 ||
    echo "pfill: note: could not install gltf-validator with npm; the GLB validator test will skip" >&2
}
install_gltf_validator

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "pfill: installing ${missing[*]}" >&2
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
