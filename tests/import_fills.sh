# Shared by the Blender add-on tests (sourced): write_import_fills PFILL DIR N
# writes the same fill of N particles (same seed and options: the same
# particles) as CSV, PLY and GLB with pfill's attribute names, and as CSV
# and PLY with Houdini's, into DIR. The spheres are of two sizes (radii
# 1:2, --radii): each must import at its own.
write_import_fills() {
  local pfill="$1" dir="$2" count="$3" out names
  for out in fill.csv fill.ply fill.glb houdini.csv houdini.ply; do
    names=pfill
    case "$out" in houdini.*) names=houdini ;; esac
    "$pfill" fill sphere -n "$count" --radii discrete:1:0.5,2:0.5 -q --colour depth --attribute-names "$names" -o "$dir/$out" >/dev/null
  done
}
