#!/usr/bin/env bash
# The Blender add-on's readers without Blender (tests/pfill_import_readers.py).
# Usage: pfill_import_readers.sh PFILL_BINARY REPO_DIR PYTHON
set -euo pipefail
pfill="$1"
repo="$2"
python="$3"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
source "$(dirname "$0")/import_fills.sh"
write_import_fills "$pfill" "$work" 150
"$python" "$repo/tests/pfill_import_readers.py" "$repo" "$work/fill.csv" \
  "$work/fill.ply" "$work/fill.glb" "$work/houdini.csv" "$work/houdini.ply"
# Far from the origin (issue 33): PLY with double positions, GLB about the
# node's translation, read back to within 1e-6 of the CSV's doubles.
printf 'v %s %s %s\n' 999999 999999.5 999999.5  1000001 999999.5 999999.5  999999 1000000.5 999999.5 \
  1000001 1000000.5 999999.5  999999 999999.5 1000000.5  1000001 999999.5 1000000.5 \
  999999 1000000.5 1000000.5  1000001 1000000.5 1000000.5 > "$work/far.obj"
printf 'f 1 3 4\nf 1 4 2\nf 5 6 8\nf 5 8 7\nf 1 2 6\nf 1 6 5\nf 3 7 8\nf 3 8 4\nf 1 5 7\nf 1 7 3\nf 2 4 8\nf 2 8 6\n' >> "$work/far.obj"
for out in far.csv far.ply far.glb; do
  "$pfill" fill "$work/far.obj" -n 150 -q --colour depth -o "$work/$out" >/dev/null
done
"$python" "$repo/tests/pfill_import_readers.py" "$repo" "$work/far.csv" "$work/far.ply" "$work/far.glb"
