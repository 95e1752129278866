/// @file birth_view.hpp
/// @brief What a birth's room test sees in this process (issue 31): the
/// centres near the sites this process decides, and which sites those are.
/// One process (the OpenCL and reference engines, LAMMPS at one rank):
/// every particle and every site. LAMMPS at P > 1 ranks: the rank's own
/// atoms plus every atom within the room test's reach of its sub-domain,
/// and the sites inside its sub-domain (each site decided by exactly one
/// rank), so no rank gathers all positions for births.
#pragma once
#include <cstddef>
#include <vector>

#include "pfill/vec3.hpp"

namespace pfill {

struct BirthView {
  std::vector<Vec3> centres;   ///< this process's particles and its halo (complete: all)
  std::vector<double> radii;   ///< their radii, in the same order
  /// The first `own` centres are this process's own particles (the rest
  /// its halo); a complete view: all of them.
  size_t own = 0;
  /// Every rank's sub-domain, in rank order, and this process's rank;
  /// empty: one process, which decides every site (a complete view).
  std::vector<Box3> regions;
  int region = 0;

  /// Whether the view holds every particle and decides every site.
  bool complete() const { return regions.empty(); }
  /// Whether this process decides the site at p.
  bool decides(const Vec3& p) const;
};

/// How far p lies outside box b (0 inside or on it).
double distance_to_box(const Box3& b, const Vec3& p);

/// The region of `regions` a point belongs to: the first whose half-open
/// box [lo, hi) holds it; a point in none goes to the nearest box. So every
/// point has exactly one region, the same on every process.
int owning_region(const std::vector<Box3>& regions, const Vec3& p);

}  // namespace pfill
