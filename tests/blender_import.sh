#!/usr/bin/env bash
# A real client: Blender (Debian 12's 3.4, headless) imports a fill written
# as PLY and as GLB with one point per particle. Registered with ctest only
# where blender is installed. Usage: blender_import.sh PFILL_BINARY REPO_DIR
set -euo pipefail
pfill="$1"
repo="$2"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
"$pfill" fill --builtin sphere -n 200 -q --colour depth -o "$work/fill.ply" --report "$work/report.json" >/dev/null
"$pfill" fill --builtin sphere -n 200 -q --colour depth -o "$work/fill.glb" >/dev/null
count="$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["metrics"]["particles"])' "$work/report.json")"
blender -b --factory-startup --python-exit-code 1 -P "$repo/scripts/blender_import_check.py" -- \
  "$count" "$work/fill.ply" "$work/fill.glb" 2>&1 | grep -E "points|expected|Error"
