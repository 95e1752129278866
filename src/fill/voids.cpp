// Finding holes in a packing that can take another sphere.
#include "pfill/voids.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <tbb/parallel_for.h>

#include "fill/centre_grid.hpp"
#include "fill/hole_climb.hpp"
#include "pfill/sdf.hpp"

namespace pfill {
namespace {

/// find_holes over the points of `sdf` (its spacing, origin and dims),
/// with the signed distance at a grid point (`at_point`) and anywhere (`at`).
/// `point_is_cheap`: `at_point` reads a stored value, so it is tested
/// before the centres (most of a box lies outside the object or near its
/// wall, and one read rules such a point out); else after them.
template <typename AtPoint, typename At>
std::vector<Vec3> holes_on_lattice(const ParticleSet& particles, const ScalarGrid& sdf, const AtPoint& at_point,
                                   bool point_is_cheap, const At& at, double radius, double clearance, size_t limit,
                                   double reference_radius, std::vector<double>* distances, const Box3* within) {
  std::vector<Vec3> holes;
  // Unequal spheres: distances to sphere surfaces, plus the reference
  // radius (so that for spheres of that radius they are centre distances).
  const bool unequal = reference_radius > 0;
  double widest = reference_radius;
  if (unequal)
    for (double r : particles.radii) widest = std::max(widest, r);
  const double shift = widest - reference_radius;  // the most a sphere's surface is nearer than its centre says
  const double reach = clearance + shift;  // nearest spheres beyond the clearance do not matter
  CentreGrid grid(particles.positions, reach);
  auto centre = [&](uint32_t id) { return id < particles.size() ? particles.positions[id] : holes[id - particles.size()]; };
  auto offset = [&](uint32_t id) {  // a taken hole counts as a sphere of the reference radius
    return unequal && id < particles.size() ? particles.radii[id] - reference_radius : 0.0;
  };
  auto nearest = [&](const Vec3& p) {
    double d = clearance;
    grid.for_near(p, [&](uint32_t id) { d = std::min(d, length(centre(id) - p) - offset(id)); });
    return d;
  };
  // Grid points whose nearest centre is within the grid's reach of the clearance ...
  const double miss = std::sqrt(3.0) * 0.5 * sdf.spacing;  // farthest a point lies from the nearest grid point
  struct Candidate {
    Vec3 p;
    double d;
  };
  const double least = std::max(0.0, clearance - miss);
  const double surely_near2 = least * least * (1 - 1e-9);  // a centre closer than this: d < clearance - miss
  // The grid points to search: all, or those in `within`.
  std::array<int, 3> first{0, 0, 0}, last = sdf.dims;
  if (within)
    for (int a = 0; a < 3; ++a) {
      first[a] = std::max(0, static_cast<int>(std::ceil((within->lo[a] - sdf.origin[a]) / sdf.spacing)));
      last[a] = std::min(sdf.dims[a], static_cast<int>(std::floor((within->hi[a] - sdf.origin[a]) / sdf.spacing)) + 1);
    }
  std::vector<std::vector<Candidate>> slices(static_cast<size_t>(std::max(0, sdf.dims[2])));
  tbb::parallel_for(first[2], std::max(first[2], last[2]), [&](int k) {  // (no hole is taken yet: `nearest` only reads)
    for (int j = first[1]; j < last[1]; ++j)
      for (int i = first[0]; i < last[0]; ++i) {
        if (point_is_cheap && -at_point(i, j, k) < radius) continue;
        const Vec3 p = sdf.point(i, j, k);
        // Most points have a centre well within the clearance: one found ends the search.
        if (grid.any_near(p, [&](uint32_t id) {
              const Vec3 v = particles.positions[id] - p;
              if (!unequal) return dot(v, v) < surely_near2;
              return length(v) - offset(id) < least * (1 - 1e-9);
            }))
          continue;
        if (!point_is_cheap && -at_point(i, j, k) < radius) continue;  // (an exact distance: dearer than the centres)
        const double d = nearest(p);
        if (d >= clearance - miss) slices[static_cast<size_t>(k)].push_back({p, d});
      }
  });
  std::vector<Candidate> cands;
  for (const auto& slice : slices) cands.insert(cands.end(), slice.begin(), slice.end());
  std::stable_sort(cands.begin(), cands.end(), [](const Candidate& a, const Candidate& b) { return a.d > b.d; });
  // ... climbed to where the nearest centre is farthest (staying r deep), and
  // taken, largest first, where that reaches the clearance.
  uint32_t next_id = static_cast<uint32_t>(particles.size());
  for (const Candidate& c : cands) {
    if (holes.size() >= limit) break;
    Vec3 p = c.p;
    if (nearest(p) < clearance - miss) continue;  // a hole taken since
    const double d = climb_to_hole_centre(p, 0.5 * sdf.spacing, 0.005 * radius, nearest,
                                          [&](const Vec3& q) { return -at(q) >= radius; });
    if (d < clearance) continue;
    holes.push_back(p);
    if (distances) distances->push_back(d);
    grid.insert(p, next_id++);
  }
  return holes;
}

}  // namespace

std::vector<Vec3> find_holes(const ParticleSet& particles, const ScalarGrid& sdf, double radius, double clearance,
                             size_t limit, double reference_radius, std::vector<double>* distances,
                             const Box3* within) {
  return holes_on_lattice(
      particles, sdf, [&sdf](int i, int j, int k) { return static_cast<double>(sdf.at(i, j, k)); }, true,
      [&sdf](const Vec3& q) { return sample(sdf, q); }, radius, clearance, limit, reference_radius, distances,
      within);
}

std::vector<Vec3> find_holes(const ParticleSet& particles, const ScalarGrid& lattice,
                             const std::function<double(const Vec3&)>& signed_distance, double radius,
                             double clearance, size_t limit, double reference_radius, std::vector<double>* distances,
                             const Box3* within) {
  return holes_on_lattice(
      particles, lattice, [&](int i, int j, int k) { return signed_distance(lattice.point(i, j, k)); }, false,
      signed_distance, radius, clearance, limit, reference_radius, distances, within);
}

}  // namespace pfill
