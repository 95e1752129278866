/// @file birth_sites.hpp
/// @brief Where particles are born: the deepest interior points of the
/// signed distance field, and the test of whether a site has room for a
/// newborn given the latest known particle positions.
#pragma once
#include <vector>

#include "pfill/grid.hpp"
#include "pfill/vec3.hpp"

namespace pfill {

struct BirthSite {
  Vec3 position;
  double depth = 0;  ///< distance to the surface (from the field)
};

/// The deepest grid point, then, `count - 1` times, the deepest grid point at
/// least `separation` times the first site's depth from every site chosen so
/// far (fewer if none is left that deep). Sites shallower than `min_depth`
/// are never chosen; the result is empty when the field has no such point.
std::vector<BirthSite> choose_birth_sites(const ScalarGrid& sdf, int count, double min_depth,
                                          double separation = 2.0);

/// True when no centre in `centres` lies closer than `clearance` to `site`.
bool site_has_room(const std::vector<Vec3>& centres, const Vec3& site, double clearance);

}  // namespace pfill
