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
#include "pfill/particle_share.hpp"

namespace pfill {
namespace {

// Spheres that touch to within rounding do not overlap.
constexpr double kTouching = 1e-9;

double max_radius(const ParticleSet& p) {
  double m = 0;
  for (double r : p.radii) m = std::max(m, r);
  return m;
}

/// Calls f(view, i, j) for each pair within `reach` that this process
/// counts: i its own, j its own and after i, or j another's (in the halo)
/// of a higher id; so every pair counts once over all processes. `view`:
/// the own spheres, then the halo.
template <class F>
void for_pairs_counted_here(const ParticleSet& own, const ParticleShare& share, double reach, F f) {
  ParticleSet joined;
  if (!share.complete()) joined = own_and_halo(own, halo_of(share, own, reach));
  const ParticleSet& view = share.complete() ? own : joined;
  if (view.size() == 0) return;
  const CentreGrid grid(view.positions, reach);
  const size_t n = own.size();
  for (size_t i = 0; i < n; ++i)
    grid.for_near(view.positions[i], [&](uint32_t j) {
      if (j < n ? j <= i : view.id(j) <= view.id(i)) return;
      f(view, i, static_cast<size_t>(j));
    });
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
                               const MetricsOptions& options, const ParticleShare& share) {
  // Held in parts (issue 31): each process measures its own spheres, and the
  // pairs whose sphere of the lower id is its own, with a halo of the
  // others'; sums and extremes over the processes. One process: all.
  ProcessGroup& group = *share.group;
  PackingMetrics m;
  m.count = static_cast<size_t>(group.sum(static_cast<double>(particles.size())));
  m.mesh_volume = mesh_volume;
  m.containment_tolerance = options.containment_tolerance;
  if (m.count == 0) return m;

  // sums: sphere volume, contained, centres outside, overlapping pairs, their overlaps, contacts
  std::vector<double> sums(6, 0.0);
  // maxima: penetration, overlap, -(closest centres over r_i + r_j)
  std::vector<double> maxima{0.0, 0.0, -std::numeric_limits<double>::infinity()};
  for (double r : particles.radii) sums[0] += 4.0 / 3.0 * kPi * r * r * r;
  const std::vector<double> sd = boundary.signed_distance(particles.positions);
  for (size_t i = 0; i < particles.size(); ++i) {
    const double r = particles.radii[i];
    const double penetration = (r + sd[i]) / r;  // > 0: the sphere pokes out by this fraction of r
    if (penetration <= options.containment_tolerance) ++sums[1];
    if (sd[i] > 0) ++sums[2];
    maxima[0] = std::max(maxima[0], penetration);
  }

  const double largest = group.max(max_radius(particles));
  const double cell = 2 * largest * (1 + options.contact_gap);
  double min_ratio = std::numeric_limits<double>::infinity();
  for_pairs_counted_here(particles, share, cell, [&](const ParticleSet& view, size_t i, size_t j) {
    // Unequal spheres: gaps and overlaps as fractions of the smaller radius.
    const double ri = view.radii[i], rj = view.radii[j], small_r = std::min(ri, rj);
    const double d = length(view.positions[j] - view.positions[i]);
    if (d < ri + rj + options.contact_gap * small_r) ++sums[5];
    if (d <= cell) min_ratio = std::min(min_ratio, d / (ri + rj));  // farther: maybe not the closest pair
    const double fraction = (ri + rj - d) / small_r;
    if (fraction > kTouching) {
      ++sums[3];
      sums[4] += fraction;
      maxima[1] = std::max(maxima[1], fraction);
    }
  });
  maxima[2] = -min_ratio;
  group.sum(sums);
  group.max(maxima);
  m.packing_fraction = mesh_volume > 0 ? sums[0] / mesh_volume : 0;
  m.contained_share = sums[1] / static_cast<double>(m.count);
  m.centres_outside = static_cast<size_t>(sums[2]);
  m.max_penetration = maxima[0];
  m.overlapping_pairs = static_cast<size_t>(sums[3]);
  m.mean_overlap = m.overlapping_pairs ? sums[4] / sums[3] : 0;
  m.max_overlap = maxima[1];
  m.mean_coordination = 2.0 * sums[5] / static_cast<double>(m.count);
  min_ratio = -maxima[2];
  // No pair within touching reach (a sparse set: --rest-distance 5 keeps
  // centres ~10 r apart): look farther, doubling the reach, rather than
  // report 0 (issue 33: "closest centres 0.000000" where the real value was 4.7).
  const Box3 own_box = particles.bounds();  // the whole set's box: the parts' boxes' extremes over all
  std::vector<double> extremes{own_box.hi.x, own_box.hi.y, own_box.hi.z, -own_box.lo.x, -own_box.lo.y, -own_box.lo.z};
  group.max(extremes);
  const double diagonal =
      length(Vec3(extremes[0] + extremes[3], extremes[1] + extremes[4], extremes[2] + extremes[5]));
  for (double reach = 4 * largest; !std::isfinite(min_ratio) && m.count > 1 && reach <= 4 * diagonal; reach *= 2) {
    for_pairs_counted_here(particles, share, reach, [&](const ParticleSet& view, size_t i, size_t j) {
      const double d = length(view.positions[j] - view.positions[i]);
      if (d <= reach) min_ratio = std::min(min_ratio, d / (view.radii[i] + view.radii[j]));
    });
    min_ratio = group.min(min_ratio);
  }
  m.min_distance = std::isfinite(min_ratio) ? min_ratio : 0;
  if (options.holes) {
    // Of the smallest radius, as the fill measures it: a hole over 1 takes
    // the smallest sphere (equal spheres: r).
    double smallest = std::numeric_limits<double>::infinity();
    for (double r : particles.radii) smallest = std::min(smallest, r);
    m.largest_hole = largest_holes(boundary, particles, group.min(smallest), share).front().gap_over_r;
  }
  return m;
}

double largest_hole_over_r(const Boundary& boundary, const ParticleSet& particles, double radius) {
  return largest_hole(boundary, particles, radius).gap_over_r;
}

ContainmentRepair repair_containment(const Boundary& boundary, ParticleSet& particles, double tolerance,
                                     double max_overlap, const ParticleShare& share) {
  ProcessGroup& group = *share.group;
  const std::vector<double> sd = boundary.signed_distance(particles.positions);
  std::vector<size_t> crossing;
  for (size_t i = 0; i < particles.size(); ++i)
    if (particles.radii[i] + sd[i] > tolerance * particles.radii[i]) crossing.push_back(i);
  if (group.sum(static_cast<double>(crossing.size())) == 0) return {};

  // Per sphere: moved, the signed distance it had, removed (the halo's too).
  constexpr size_t kMoved = 0, kDistance = 1, kRemoved = 2, kWidth = 3;
  std::vector<double> state(kWidth * particles.size(), 0.0);
  for (size_t i = 0; i < particles.size(); ++i) state[kWidth * i + kDistance] = sd[i];
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
      state[kWidth * i + kRemoved] = 1;  // no room: the part is thinner than the sphere here
      continue;
    }
    particles.positions[i] = p;
    state[kWidth * i + kMoved] = 1;
  }
  // A moved sphere that now overlaps another over the bound gives way to
  // it when the other did not move, or moved from further in (ties: the
  // higher id gives way). Decided by each sphere's process alone, so the
  // same on either side of a border: a halo of the others' as moved.
  std::vector<double> halo_state;
  const ParticleSet view = own_and_halo(
      particles, halo_of(share, particles, 2 * group.max(max_radius(particles)), state, kWidth, &halo_state));
  state.insert(state.end(), halo_state.begin(), halo_state.end());
  auto at = [&](size_t i, size_t what) { return state[kWidth * i + what]; };
  auto gives_way = [&](size_t a, size_t b) {  // a to b
    if (at(a, kMoved) == 0) return false;
    if (at(b, kMoved) == 0) return true;
    return at(a, kDistance) != at(b, kDistance) ? at(a, kDistance) > at(b, kDistance) : view.ids[a] > view.ids[b];
  };
  std::vector<bool> remove(particles.size(), false);
  for (size_t i = 0; i < particles.size(); ++i) remove[i] = at(i, kRemoved) != 0;
  for (const Overlap& o : find_overlaps(view, max_overlap)) {
    if (at(o.i, kRemoved) != 0 || at(o.j, kRemoved) != 0) continue;
    if (o.i < particles.size() && gives_way(o.i, o.j)) remove[o.i] = true;
    if (o.j < particles.size() && gives_way(o.j, o.i)) remove[o.j] = true;
  }
  ContainmentRepair result;
  ParticleSet kept;
  for (size_t i = 0; i < particles.size(); ++i) {
    if (remove[i]) {
      ++result.removed;
      continue;
    }
    if (at(i, kMoved) != 0) ++result.moved;
    kept.positions.push_back(particles.positions[i]);
    kept.radii.push_back(particles.radii[i]);
    if (!particles.colours.empty()) kept.colours.push_back(particles.colours[i]);
    if (!particles.velocities.empty()) kept.velocities.push_back(particles.velocities[i]);
    if (!particles.ids.empty()) kept.ids.push_back(particles.ids[i]);
  }
  particles = std::move(kept);
  result.moved = static_cast<size_t>(group.sum(static_cast<double>(result.moved)));
  result.removed = static_cast<size_t>(group.sum(static_cast<double>(result.removed)));
  return result;
}

}  // namespace pfill
