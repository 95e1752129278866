#!/usr/bin/env bash
# The README's first command: set up, build, and run pfill's main job.
# With no arguments it fills the built-in torus (torus_particles.ply and a
# preview picture, torus_particles.png, in this folder); arguments go to pfill.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
if [ $# -eq 0 ]; then
  set -- fill --builtin torus --preview torus_particles.png
fi
exec build/pfill "$@"
