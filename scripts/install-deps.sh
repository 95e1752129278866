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
)

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
