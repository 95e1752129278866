// Checks of FillOptions before a fill (fill_options_check.cpp). Each message
// names the setting by its C++ (and Python) name, e.g. "rest_distance must be
// 1..10"; the command line swaps in its flag (cli: fill_option_flag_names).
#pragma once
#include "pfill/fill.hpp"
#include "pfill/mesh.hpp"

namespace pfill {

/// Throws pfill::Error (one line) for a setting out of its range; needs no
/// mesh, so callers can check before loading one (also in pfill/fill.hpp).
void check_fill_options(const FillOptions& options);

/// What only the mesh and the radius decide: a birth point inside the mesh's
/// box, a radius that a sphere of the box could hold, damping that leaves
/// motion. `mesh` and `options.birth_point` in the same coordinates.
void check_fill_options(const FillOptions& options, const Mesh& mesh, double radius);

/// The mesh in its own coordinates (before the fill centres it): refuses one
/// so far from the origin that doubles there are spaced by more than 1% of
/// `radius` (spot at 1e14: the fill's own summary said 0.08% overlaps, its
/// particles, moved back, overlapped by 13%).
void check_coordinates_resolve(const Mesh& mesh, double radius);

}  // namespace pfill
