#!/usr/bin/env bash
# The README's first command: set up, build, and run pfill's main job.
# With no arguments it runs on a built-in shape; any arguments go to pfill.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
if [ $# -eq 0 ]; then
  set -- info --builtin torus
fi
exec build/pfill "$@"
