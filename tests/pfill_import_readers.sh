#!/usr/bin/env bash
# The Blender add-on's readers without Blender (tests/pfill_import_readers.py).
# Usage: pfill_import_readers.sh PFILL_BINARY REPO_DIR PYTHON
set -euo pipefail
pfill="$1"
repo="$2"
python="$3"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
for out in fill.csv fill.ply fill.glb houdini.csv houdini.ply; do
  names=pfill
  case "$out" in houdini.*) names=houdini ;; esac
  "$pfill" fill sphere -n 150 -q --colour depth --attribute-names "$names" -o "$work/$out" >/dev/null
done
"$python" "$repo/tests/pfill_import_readers.py" "$repo" "$work/fill.csv" \
  "$work/fill.ply" "$work/fill.glb" "$work/houdini.csv" "$work/houdini.ply"
