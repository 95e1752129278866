#!/usr/bin/env bash
# Configures and builds pfill (Release) into ./build, using both cores.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE="${PFILL_BUILD_TYPE:-Release}" >/dev/null
cmake --build build -j"$(nproc)"
