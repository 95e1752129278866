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

constexpr double kPi = 3.14159265358979323846;
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
      const double fraction = (ri + rj - d) / (0.5 * (ri + rj));
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
      const double ri = particles.radii[i], rj = particles.radii[j], mean_r = 0.5 * (ri + rj);
      const double d = length(particles.positions[j] - particles.positions[i]);
      if (d < ri + rj + options.contact_gap * mean_r) ++contacts;
      if (d <= cell) min_ratio = std::min(min_ratio, d / (ri + rj));  // farther: maybe not the closest pair
      const double fraction = (ri + rj - d) / mean_r;
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
    double mean_r = 0;
    for (double r : particles.radii) mean_r += r;
    m.largest_hole = largest_hole_over_r(boundary, particles, mean_r / particles.size());
  }
  return m;
}

double largest_hole_over_r(const Boundary& boundary, const ParticleSet& particles, double radius) {
  return largest_hole(boundary, particles, radius).gap_over_r;
}

Hole largest_hole(const Boundary& boundary, const ParticleSet& particles, double radius) {
  if (particles.size() == 0 || !(radius > 0)) return {};
  const double reach = 3 * radius;  // nearest surfaces searched this far: holes over 2 r count as 2 r
  const CentreGrid grid(particles.positions, reach);
  // Distance from p to the nearest sphere's surface (reach - radius when none is in reach).
  auto gap = [&](const Vec3& p) {
    double g = reach - radius;
    grid.for_near(p, [&](uint32_t i) { g = std::min(g, length(particles.positions[i] - p) - particles.radii[i]); });
    return g;
  };
  auto near_any = [&](const Vec3& p) {
    bool any = false;
    grid.for_near(p, [&](uint32_t i) { any = any || length(particles.positions[i] - p) < reach; });
    return any;
  };
  Box3 box;
  for (const Vec3& c : particles.positions) box.add(c);
  const double h = 0.5 * radius;
  const Vec3 lo = box.lo - Vec3(reach, reach, reach);
  const int nx = static_cast<int>(std::ceil((box.hi.x - box.lo.x + 2 * reach) / h)) + 1;
  const int ny = static_cast<int>(std::ceil((box.hi.y - box.lo.y + 2 * reach) / h)) + 1;
  const int nz = static_cast<int>(std::ceil((box.hi.z - box.lo.z + 2 * reach) / h)) + 1;
  // Grid points near the spheres with room beyond `floor_gap`, by slices
  // in parallel, largest gap first. A candidate is 16 bytes (its gap and
  // its grid index; its point is recomputed): over no floor there are ~20 a
  // sphere, which at 32 bytes made 0.6 GiB at 1e6 spheres.
  struct Candidate {
    double gap;
    uint64_t at;  // i | j << 21 | k << 42
  };
  constexpr uint64_t kAxis = (uint64_t(1) << 21) - 1;
  if (static_cast<uint64_t>(std::max({nx, ny, nz})) > kAxis)
    throw Error("largest hole: the packing spans more than 2^21 grid points of r / 2 along an axis");
  auto point = [&](uint64_t at) {
    return lo + Vec3(static_cast<double>(at & kAxis), static_cast<double>((at >> 21) & kAxis),
                     static_cast<double>(at >> 42)) * h;
  };
  auto collect = [&](double floor_gap) {
    std::vector<std::vector<Candidate>> slices(static_cast<size_t>(nz));
    tbb::parallel_for(0, nz, [&](int k) {
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
          const Vec3 p = lo + Vec3(i, j, k) * h;
          if (!near_any(p)) continue;
          const double g = gap(p);
          if (g > floor_gap)
            slices[static_cast<size_t>(k)].push_back(
                {g, static_cast<uint64_t>(i) | static_cast<uint64_t>(j) << 21 | static_cast<uint64_t>(k) << 42});
        }
    });
    size_t total = 0;
    for (const auto& s : slices) total += s.size();
    std::vector<Candidate> cands;
    cands.reserve(total);
    for (auto& s : slices) {
      cands.insert(cands.end(), s.begin(), s.end());
      std::vector<Candidate>().swap(s);
    }
    std::sort(cands.begin(), cands.end(), [&](const Candidate& a, const Candidate& b) {
      if (a.gap != b.gap) return a.gap > b.gap;
      const Vec3 pa = point(a.at), pb = point(b.at);
      return std::tie(pa.x, pa.y, pa.z) < std::tie(pb.x, pb.y, pb.z);
    });
    return cands;
  };
  // The largest gaps first, each checked for depth >= r with exact distances,
  // until no unchecked point can beat the best (points outside the mesh fail).
  auto deep = [&](const Vec3& p) { return boundary.fast_signed_distance(p, std::numeric_limits<double>::infinity()) <= -radius; };
  double best = 0;
  Vec3 best_at;
  std::vector<Candidate> accepted;
  auto search = [&](const std::vector<Candidate>& cands) {
    best = 0;
    best_at = Vec3();
    accepted.clear();
    constexpr size_t kBatch = 4096;
    for (size_t first = 0; first < cands.size() && cands[first].gap > best - h; first += kBatch) {
      const size_t last = std::min(cands.size(), first + kBatch);
      std::vector<uint8_t> ok(last - first);
      tbb::parallel_for(first, last, [&](size_t c) { ok[c - first] = deep(point(cands[c].at)); });
      for (size_t c = first; c < last; ++c)
        if (ok[c - first]) {
          if (cands[c].gap > best) {
            best = cands[c].gap;
            best_at = point(cands[c].at);
          }
          accepted.push_back(cands[c]);
        }
    }
  };
  // Only the points within h of the best decide (the batches stop below
  // that, the seeds too): first those over a floor, which holds them
  // whenever the best lies more than h above it (nearly always: a packing's
  // largest hole is ~0.9 r); else, all of them, as the floor may have hidden
  // a deeper or a closer one. The same answer either way, from fewer points.
  const double floor_gap = 0.2 * radius;
  search(collect(floor_gap));
  if (!(best - h > floor_gap)) search(collect(0));
  // Climb from the best grid points (distinct holes) to the local maximum of
  // the gap, staying at least r deep: the grid misses up to 0.43 r.
  std::vector<Vec3> seeds;
  for (const Candidate& c : accepted) {
    if (c.gap < best - h || seeds.size() >= 64) break;
    const Vec3 p = point(c.at);
    bool seen = false;
    for (const Vec3& s : seeds) seen = seen || length(s - p) < radius;
    if (!seen) seeds.push_back(p);
  }
  std::vector<double> climbed(seeds.size(), 0);
  std::vector<Vec3> climbed_to(seeds.size());
  tbb::parallel_for(size_t(0), seeds.size(), [&](size_t k) {
    Vec3 p = seeds[k];
    double g = gap(p);
    static const Vec3 dirs[] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1},
                                {1, 1, 1}, {1, 1, -1}, {1, -1, 1}, {1, -1, -1}, {-1, 1, 1}, {-1, 1, -1},
                                {-1, -1, 1}, {-1, -1, -1}};
    for (double step = 0.5 * h; step > 0.002 * radius;) {
      bool moved = false;
      for (const Vec3& d : dirs) {
        const Vec3 q = p + d * (step / length(d));
        const double gq = gap(q);
        if (gq > g && deep(q)) {
          p = q;
          g = gq;
          moved = true;
        }
      }
      if (!moved) step *= 0.5;
    }
    climbed[k] = g;
    climbed_to[k] = p;
  });
  for (size_t k = 0; k < climbed.size(); ++k)
    if (climbed[k] > best) {
      best = climbed[k];
      best_at = climbed_to[k];
    }
  return {best_at, best / radius};
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
