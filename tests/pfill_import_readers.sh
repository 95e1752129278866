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
