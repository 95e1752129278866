// Checks of FillOptions before a fill (fill_options_check.cpp). Each message
// names the setting by its one name (the field, the Python keyword), e.g.
// "rest_distance must be 1..10"; the command line shows its flag instead
// (with_flags, fill_settings.hpp).
#pragma once
#include <cstddef>

#include "pfill/fill.hpp"
#include "pfill/mesh.hpp"

namespace pfill {

/// The most particles a fill takes on (about 30 GiB of device memory).
constexpr size_t kMaxParticles = 100'000'000;

/// Throws pfill::Error (one line) naming the first setting of `o` out of its
/// range; NaN fails every test. Needs no mesh, so callers can check before
/// loading one (declared for them in fill_settings.hpp).
void check_fill_options(const FillOptions& o);

/// What only the mesh and the radius decide: a birth point inside the mesh's
/// box, a radius that a sphere of the box could hold, damping that leaves
/// motion. `mesh` and `o.birth` in the same coordinates.
void check_fill_options(const FillOptions& o, const Mesh& mesh, double radius);

/// The mesh in its own coordinates (before the fill centres it): refuses one
/// so far from the origin that doubles there are spaced by more than 1% of
/// `radius` (spot at 1e14: the fill's own summary said 0.08% overlaps, its
/// particles, moved back, overlapped by 13%).
void check_coordinates_resolve(const Mesh& mesh, double radius);

}  // namespace pfill
