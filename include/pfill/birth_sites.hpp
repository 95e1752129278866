/// @file birth_sites.hpp
/// @brief Where particles are born: the deepest interior points of the
/// signed distance field, and the test of whether a site has room for a
/// newborn given the latest known particle positions.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "pfill/grid.hpp"
#include "pfill/vec3.hpp"

namespace pfill {

struct BirthSite {
  Vec3 position;
  double depth = 0;  ///< distance to the surface (from the field)
};

/// The closed parts of a field's inside (6-connected samples below 0) and
/// what add_sites_per_part did with them.
struct PartSites {
  size_t parts = 0;      ///< parts with an inside sample
  size_t added = 0;      ///< parts that had no site and got one (their deepest sample)
  size_t too_small = 0;  ///< parts whose deepest sample is less than min_depth inside
};

/// Gives every closed part of the inside that is at least `min_depth` deep
/// a site (its deepest sample) when none of `sites` lies in it, so a mesh of
/// many separate parts fills them all (issue 33: 216 separate spheres got 4
/// sites and 127 stayed empty); counts the parts too thin for that.
PartSites add_sites_per_part(const ScalarGrid& sdf, double min_depth, std::vector<BirthSite>& sites);

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

/// Unequal spheres: true when no sphere (centres, radii) lies closer to
/// `site` than `share` (radius + its radius), `radius` the newborn's.
bool site_has_room(const std::vector<Vec3>& centres, const std::vector<double>& radii, const Vec3& site,
                   double radius, double share);

/// A site in a pocket too small for newborns to move on from (a small
/// closed part of the mesh, a few spheres wide) takes them without end:
/// those before sit against the wall round its empty middle, so the room
/// test passes wave after wave (found 2026-12-07: a part of 2.2 radii
/// took thousands into room for four, and pass 1 never ended). Its
/// inscribed ball (radius: the site's depth) holds at most Kepler's
/// 0.7405 (depth / r)^3 spheres of radius r, so a site with that many
/// centres within depth - r / 2 of it is full. A bulk packing holds less
/// than 0.9 of the bound there, so only pockets reach it; sites deeper
/// than kPocketDepth radii are not tested (their pockets hold dozens and
/// the packing in them moves on).
constexpr double kPocketDepth = 4;
/// The bound for a site of `radius`'s spheres; 0 where the site is too deep to test.
size_t pocket_capacity(const BirthSite& site, double radius);
/// Whether `site`'s pocket is full (by `centres`; every centre visited).
bool pocket_full(const std::vector<Vec3>& centres, const BirthSite& site, double radius);

/// Sites spread over the whole interior, for births in waves: among field
/// points at least `min_depth` deep (taken on a sub-lattice of the field,
/// about `spacing` / 3 apart), the deepest, then again and again the
/// deepest that lies at least `spacing` from every site chosen so far. The
/// sites cover every part of the object at least 2 `min_depth` thick, one
/// per ~`spacing`^3 of volume, so their number grows with the volume (and a
/// fill's count) while each feeds a neighbourhood of the same size.
/// Empty when no point is that deep.
std::vector<BirthSite> spread_birth_sites(const ScalarGrid& sdf, double spacing, double min_depth);

/// The birth-room test for many sites at once: the centres of a snapshot
/// binned into cells of the clearance (built in O(n)); a query visits the
/// 27 cells around a site, so a wave over every site costs O(n + sites),
/// not O(n * sites).
class RoomGrid {
 public:
  RoomGrid() = default;
  RoomGrid(const std::vector<Vec3>& centres, double clearance);
  /// Unequal spheres: room for a newborn of radius r where no sphere j lies
  /// closer than `share` (r + r_j); cells for newborns up to `largest`.
  RoomGrid(const std::vector<Vec3>& centres, const std::vector<double>& radii, double share, double largest);
  /// True when no centre lies closer than the clearance to `site`.
  bool has_room(const Vec3& site) const;
  /// Unequal spheres (the second constructor): room for a newborn of `radius`.
  bool has_room(const Vec3& site, double radius) const;
  /// pocket_full by the grid's centres (the cells within the pocket's reach).
  bool pocket_full(const BirthSite& site, double radius) const;

 private:
  bool cell_of(const Vec3& p, std::array<int, 3>& c) const;
  size_t cell_index(const std::array<int, 3>& c) const {
    return static_cast<size_t>(c[0]) +
           static_cast<size_t>(dims_[0]) * (static_cast<size_t>(c[1]) + static_cast<size_t>(dims_[1]) * c[2]);
  }
  double clearance_ = 0;
  double cell_ = 1;
  Vec3 origin_;
  std::array<int, 3> dims_{0, 0, 0};
  std::vector<uint32_t> start_;  ///< cell c's centres: sorted_[start_[c] .. start_[c + 1])
  std::vector<Vec3> sorted_;     ///< the centres in cell order
  std::vector<double> radii_;    ///< unequal spheres: their radii in the same order
  double share_ = 0;
};

}  // namespace pfill
