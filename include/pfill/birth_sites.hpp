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

/// The deepest grid point, then, `count - 1` times, the grid point farthest
/// from all sites chosen so far among the points at least `depth_share` as
/// deep as the deepest (farthest-point sampling of the deep core: sites
/// spread over the object's main rooms, e.g. round a torus, while staying
/// deep). The inscribed balls of two sites (radius: their depth) never
/// overlap, so each site feeds a room of its own (fewer sites when there is
/// no such point); no site is shallower than `min_depth`, and the result is
/// empty when the field has no point that deep.
std::vector<BirthSite> choose_birth_sites(const ScalarGrid& sdf, int count, double min_depth,
                                          double depth_share = 0.75);

/// True when no centre in `centres` lies closer than `clearance` to `site`.
bool site_has_room(const std::vector<Vec3>& centres, const Vec3& site, double clearance);

}  // namespace pfill
