#!/usr/bin/env bash
# The Blender add-on (blender/pfill_import.py) in Debian's Blender, headless:
# a fill written as PLY, GLB, CSV and Houdini-named CSV and PLY imports as one
# sphere instance per particle with the file's radii, colours and ids (see
# scripts/blender_pfill_import_check.py). Registered with ctest only where
# blender is installed. Usage: blender_pfill_import.sh PFILL_BINARY REPO_DIR
set -euo pipefail
pfill="$1"
repo="$2"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
source "$(dirname "$0")/import_fills.sh"
write_import_fills "$pfill" "$work" 200
blender -b --factory-startup --python-exit-code 1 -P "$repo/scripts/blender_pfill_import_check.py" -- \
  "$repo" "$work/fill.csv" "$work/fill.ply" "$work/fill.glb" "$work/fill.csv" "$work/houdini.csv" "$work/houdini.ply" 2>&1 |
  grep -E "^  |^/|blender pfill_import|Error|Traceback|line [0-9]"
