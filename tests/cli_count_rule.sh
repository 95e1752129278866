#!/usr/bin/env bash
# One count rule: the radius `pfill info` lists for N particles is the one
# `pfill fill -n N` uses, on a built-in shape and (when ../shared exists) spot.
set -u
here="$(cd "$(dirname "$0")" && pwd)"
source "$here/cli_test_lib.sh"

same_radius() {  # MESH N: info's radius for N against fill -n N's
  local mesh="$1" n="$2" info fill
  info=$("$pfill" info "$mesh" --json | python3 -c "
import json, sys
print([r['radius'] for r in json.load(sys.stdin)['radius_for_count'] if r['count'] == $n][0])")
  # The radius is chosen before any step: a short pass 1 is enough to read it.
  fill=$("$pfill" fill "$mesh" -n "$n" --max-steps 50 --settle-steps 1 --hole-rounds 0 -o f.csv --json -q 2>/dev/null |
         python3 -c "import json, sys; print(json.load(sys.stdin)['radius'])")
  python3 -c "import sys; a, b = $info, $fill; sys.exit(0 if abs(a - b) <= 1e-9 * abs(b) else 1)" ||
    fail "$mesh -n $n: info lists radius $info, fill uses $fill"
}

same_radius sphere 1000
same_radius torus 10000
spot="$here/../../shared/meshes/spot.obj"
if [ -f "$spot" ]; then
  same_radius "$spot" 1000
else
  echo "spot.obj not found (../shared/meshes): that case skipped"
fi

if [ "$failures" -eq 0 ]; then echo "cli count rule: all passed"; else exit 1; fi
