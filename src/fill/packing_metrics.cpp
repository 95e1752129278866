// Exact quality measures of a sphere packing in a mesh, and the final
// containment repair (see include/pfill/packing_metrics.hpp).
#include "pfill/packing_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>

#include <limits>

#include <tbb/parallel_for.h>

#include "fill/centre_grid.hpp"
#include "pfill/error.hpp"

namespace pfill {
namespace {

// Spheres that touch to within rounding do not overlap.
constexpr double kTouching = 1e-9;

double max_radius(const ParticleSet& p) {
  double m = 0;
  for (double r : p.radii) m = std::max(m, r);
  return m;
}

}  // namespace

std::vector<Overlap> find_overlaps(const ParticleSet& particles, double min_fraction) {
  std::vector<Overlap> out;
  if (particles.size() < 2) return out;
  const CentreGrid grid(particles.positions, 2 * max_radius(particles));
  for (size_t i = 0; i < particles.size(); ++i) {
    grid.for_near(particles.positions[i], [&](uint32_t j) {
      if (j <= i) return;
      const double ri = particles.radii[i], rj = particles.radii[j];
      const double d = length(particles.positions[j] - particles.positions[i]);
      const double fraction = (ri + rj - d) / std::min(ri, rj);  // of the smaller radius (issue 29)
      if (fraction > kTouching && fraction > min_fraction) out.push_back({static_cast<uint32_t>(i), j, fraction});
    });
  }
  return out;
}

PackingMetrics measure_packing(const Boundary& boundary, double mesh_volume, const ParticleSet& particles,
                               const MetricsOptions& options) {
  PackingMetrics m;
  m.count = particles.size();
  m.mesh_volume = mesh_volume;
  m.containment_tolerance = options.containment_tolerance;
  if (particles.size() == 0) return m;

  double sphere_volume = 0;
  for (double r : particles.radii) sphere_volume += 4.0 / 3.0 * kPi * r * r * r;
  m.packing_fraction = mesh_volume > 0 ? sphere_volume / mesh_volume : 0;

  const std::vector<double> sd = boundary.signed_distance(particles.positions);
  size_t contained = 0;
  for (size_t i = 0; i < particles.size(); ++i) {
    const double r = particles.radii[i];
    const double penetration = (r + sd[i]) / r;  // > 0: the sphere pokes out by this fraction of r
    if (penetration <= options.containment_tolerance) ++contained;
    if (sd[i] > 0) ++m.centres_outside;
    m.max_penetration = std::max(m.max_penetration, penetration);
  }
  m.contained_share = static_cast<double>(contained) / particles.size();

  const double cell = 2 * max_radius(particles) * (1 + options.contact_gap);
  const CentreGrid grid(particles.positions, cell);
  size_t contacts = 0;
  double overlap_sum = 0;
  double min_ratio = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < particles.size(); ++i) {
    grid.for_near(particles.positions[i], [&](uint32_t j) {
      if (j <= i) return;
      // Unequal spheres: gaps and overlaps as fractions of the smaller radius.
      const double ri = particles.radii[i], rj = particles.radii[j], small_r = std::min(ri, rj);
      const double d = length(particles.positions[j] - particles.positions[i]);
      if (d < ri + rj + options.contact_gap * small_r) ++contacts;
      if (d <= cell) min_ratio = std::min(min_ratio, d / (ri + rj));  // farther: maybe not the closest pair
      const double fraction = (ri + rj - d) / small_r;
      if (fraction > kTouching) {
        ++m.overlapping_pairs;
        overlap_sum += fraction;
        m.max_overlap = std::max(m.max_overlap, fraction);
      }
    });
  }
  m.mean_overlap = m.overlapping_pairs ? overlap_sum / m.overlapping_pairs : 0;
  m.mean_coordination = 2.0 * contacts / particles.size();
  // No pair within touching reach (a sparse set: --rest-distance 5 keeps
  // centres ~10 r apart): look farther, doubling the reach, rather than
  // report 0 (issue 33: "closest centres 0.000000" where the real value was 4.7).
  const double diagonal = particles.bounds().diagonal();
  for (double reach = 4 * max_radius(particles); !std::isfinite(min_ratio) && particles.size() > 1 && reach <= 4 * diagonal;
       reach *= 2) {
    const CentreGrid wide(particles.positions, reach);
    for (size_t i = 0; i < particles.size(); ++i)
      wide.for_near(particles.positions[i], [&](uint32_t j) {
        if (j <= i) return;
        const double d = length(particles.positions[j] - particles.positions[i]);
        if (d <= reach) min_ratio = std::min(min_ratio, d / (particles.radii[i] + particles.radii[j]));
      });
  }
  m.min_distance = std::isfinite(min_ratio) ? min_ratio : 0;
  if (options.holes) {
    // Of the smallest radius, as the fill measures it: a hole over 1 takes
    // the smallest sphere (equal spheres: r).
    const double smallest = *std::min_element(particles.radii.begin(), particles.radii.end());
    m.largest_hole = largest_hole_over_r(boundary, particles, smallest);
  }
  return m;
}

double largest_hole_over_r(const Boundary& boundary, const ParticleSet& particles, double radius) {
  return largest_hole(boundary, particles, radius).gap_over_r;
}

ContainmentRepair repair_containment(const Boundary& boundary, ParticleSet& particles, double tolerance,
                                     double max_overlap) {
  ContainmentRepair result;
  if (particles.size() == 0) return result;
  const std::vector<double> sd = boundary.signed_distance(particles.positions);
  std::vector<size_t> crossing;
  for (size_t i = 0; i < particles.size(); ++i)
    if (particles.radii[i] + sd[i] > tolerance * particles.radii[i]) crossing.push_back(i);
  if (crossing.empty()) return result;

  std::vector<bool> remove(particles.size(), false);
  std::vector<Vec3> moved_to(crossing.size());
  tbb::parallel_for(size_t(0), crossing.size(), [&](size_t k) {
    const size_t i = crossing[k];
    const ClosestPoint c = boundary.closest(particles.positions[i]);
    // The outward normal points out of the solid from the closest point.
    moved_to[k] = c.point - c.normal * particles.radii[i];
  });
  for (size_t k = 0; k < crossing.size(); ++k) {
    const size_t i = crossing[k];
    const Vec3 p = moved_to[k];
    const double depth = -boundary.signed_distance(p);
    if (!(depth >= particles.radii[i] * (1 - tolerance))) {
      remove[i] = true;  // no room: the part is thinner than the sphere here
      continue;
    }
    particles.positions[i] = p;
  }
  // A moved sphere that now overlaps too much gives way.
  // When both moved, the one that was further out gives way.
  for (const Overlap& o : find_overlaps(particles, max_overlap)) {
    if (remove[o.i] || remove[o.j]) continue;
    const bool i_moved = std::binary_search(crossing.begin(), crossing.end(), o.i);
    const bool j_moved = std::binary_search(crossing.begin(), crossing.end(), o.j);
    if (i_moved && (!j_moved || sd[o.i] >= sd[o.j])) remove[o.i] = true;
    else if (j_moved) remove[o.j] = true;
  }
  ParticleSet kept;
  for (size_t i = 0; i < particles.size(); ++i) {
    if (remove[i]) {
      ++result.removed;
      continue;
    }
    kept.positions.push_back(particles.positions[i]);
    kept.radii.push_back(particles.radii[i]);
    if (!particles.colours.empty()) kept.colours.push_back(particles.colours[i]);
    if (!particles.velocities.empty()) kept.velocities.push_back(particles.velocities[i]);
    if (!particles.ids.empty()) kept.ids.push_back(particles.ids[i]);
  }
  result.moved = 0;
  for (size_t i : crossing)
    if (!remove[i]) ++result.moved;
  particles = std::move(kept);
  return result;
}

}  // namespace pfill
