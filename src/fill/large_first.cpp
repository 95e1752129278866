// Rare large spheres placed before pass 1 (large_first.hpp).
#include "fill/large_first.hpp"

#include <algorithm>
#include <cstring>
#include <limits>

#include "fill/counter_rng.hpp"
#include "fill/pick_over_processes.hpp"
#include "fill/site_choice.hpp"

namespace pfill {
namespace {

// Candidate points: the field's samples on a sub-lattice about this share
// of the smallest radius apart (finer gains little: a sphere's room is
// decided within a few spacings), and the first sphere tried at this many
// starts spread over its points.
constexpr double kLattice = 1.0 / 8;
constexpr size_t kStarts = 64;

std::vector<LargeCandidate> candidates(const ScalarGrid& field, double min_depth) {
  const int stride = std::max(1, static_cast<int>(kLattice * min_depth / field.spacing));
  std::vector<LargeCandidate> out;
  for (int k = 0; k < field.dims[2]; k += stride)
    for (int j = 0; j < field.dims[1]; j += stride)
      for (int i = 0; i < field.dims[0]; i += stride) {
        const double depth = -static_cast<double>(field.at(i, j, k));
        if (depth >= min_depth) out.push_back({field.point(i, j, k), depth, out.size()});
      }
  return out;
}

/// This process's pick made the group's (one process: itself).
using Combine = std::function<Pick(const Pick& mine, bool farthest)>;

struct Attempt {
  LargePlacement placed;
  double slack = -std::numeric_limits<double>::infinity();  ///< the closest pair's room to spare
  bool better_than(const Attempt& o) const {
    return placed.centres.size() > o.placed.centres.size() ||
           (placed.centres.size() == o.placed.centres.size() && slack > o.slack);
  }
};

/// From `start`, each next sphere at the fitting candidate farthest
/// (surface to surface) from the ones placed so far (`farthest`), or at the
/// shallowest fitting one (pushed to the wall, it leaves the most room).
Attempt place_from(const std::vector<LargeCandidate>& c, const Vec3& start, const std::vector<double>& radii,
                   const LargeFirstSettings& s, bool farthest, const Combine& combine) {
  Attempt a;
  // gap[p]: the least of |p - c_j| - r_j over the spheres placed so far.
  std::vector<double> gap(c.size(), std::numeric_limits<double>::infinity());
  auto put = [&](const Vec3& at, double r) {
    a.placed.centres.push_back(at);
    a.placed.radii.push_back(r);
    for (size_t q = 0; q < c.size(); ++q) gap[q] = std::min(gap[q], length(c[q].point - at) - r);
  };
  put(start, radii[0]);
  for (size_t i = 1; i < radii.size(); ++i) {
    size_t best = c.size();
    for (size_t q = 0; q < c.size(); ++q)
      if (c[q].depth >= radii[i] + s.wall_gap && gap[q] >= radii[i] + s.pair_gap &&
          (best == c.size() || (farthest ? gap[q] > gap[best] : c[q].depth < c[best].depth)))
        best = q;
    const Pick p = combine(best == c.size() ? Pick{} : Pick{c[best].point, gap[best], c[best].depth, c[best].order, 1},
                           farthest);
    if (!p.found) continue;  // no room for this one; a smaller one may still fit
    a.slack = std::min(a.slack == -std::numeric_limits<double>::infinity() ? p.gap : a.slack,
                       p.gap - radii[i] - s.pair_gap);
    put(p.point, radii[i]);
  }
  return a;
}

/// The best attempt over the starts, each both ways (the first to place every sphere ends the search).
LargePlacement best_of(const std::vector<LargeCandidate>& c, const std::vector<Vec3>& starts,
                       const std::vector<double>& radii, const LargeFirstSettings& s, const Combine& combine) {
  Attempt best;
  for (const Vec3& start : starts) {
    for (bool farthest : {true, false}) {
      Attempt a = place_from(c, start, radii, s, farthest, combine);
      if (a.better_than(best)) best = std::move(a);
    }
    if (best.placed.centres.size() == radii.size()) break;  // all fit
  }
  return best.placed;
}

std::vector<double> without_first(const std::vector<double>& radii) {
  return std::vector<double>(radii.begin() + 1, radii.end());
}

}  // namespace

LargePlacement place_large_first(const ScalarGrid& field, const std::vector<double>& radii,
                                 const LargeFirstSettings& s) {
  if (radii.empty()) return {};
  const double smallest = *std::min_element(radii.begin(), radii.end());
  const std::vector<LargeCandidate> c = candidates(field, smallest + s.wall_gap);
  std::vector<size_t> first;  // the first sphere's points
  for (size_t q = 0; q < c.size(); ++q)
    if (c[q].depth >= radii[0] + s.wall_gap) first.push_back(q);
  if (first.empty())  // the first does not fit: try without it
    return radii.size() < 2 ? LargePlacement{} : place_large_first(field, without_first(radii), s);
  // Starts: spread over the first sphere's points, and its shallowest.
  std::vector<Vec3> starts;
  for (size_t k = 0; k < first.size(); k += std::max<size_t>(1, first.size() / kStarts))
    starts.push_back(c[first[k]].point);
  starts.push_back(c[*std::min_element(first.begin(), first.end(), [&](size_t a, size_t b) {
                     return c[a].depth < c[b].depth;
                   })].point);
  return best_of(c, starts, radii, s, [](const Pick& mine, bool) { return mine; });
}

HeldCandidates mesh_candidates(const Boundary& boundary, const Box3& box, double step, double min_depth,
                               const BirthView& view) {
  const SiteLattice lattice(box, 3 * step, min_depth);  // (its candidates a third of the spacing apart)
  // This region and a step around it (owning_region settles the border).
  const Box3 asked = lattice.extent_near(view.regions, view.region, step);
  HeldCandidates held;
  for (const std::vector<DeepPoint>& block : deep_points_in(boundary, lattice, asked))
    for (const DeepPoint& d : block) {
      const Vec3 p = lattice.point(d.lattice);
      if (view.complete() || owning_region(view.regions, p) == view.region)
        held.points.push_back({p, d.depth, d.lattice});
    }
  std::sort(held.points.begin(), held.points.end(),
            [](const LargeCandidate& a, const LargeCandidate& b) { return a.order < b.order; });
  return held;
}

namespace {

/// The first sphere's starts over the processes: the points with the
/// kStarts smallest hashes of their order, in hash order, then the shallowest.
std::vector<Vec3> spread_starts(const std::vector<LargeCandidate>& c, double first_depth, ProcessGroup& group) {
  std::vector<Pick> hashed;  // (the hash in `gap`'s place: a pick by the least)
  Pick shallowest;
  for (const LargeCandidate& q : c) {
    if (q.depth < first_depth) continue;
    hashed.push_back({q.point, static_cast<double>(CounterRng::mix(q.order) >> 11), q.depth, q.order, 1});
    const Pick p{q.point, 0, q.depth, q.order, 1};
    if (beats(p, shallowest, false)) shallowest = p;
  }
  auto by_hash = [](const Pick& a, const Pick& b) { return a.gap < b.gap || (a.gap == b.gap && a.order < b.order); };
  const size_t keep = std::min(hashed.size(), kStarts);
  std::partial_sort(hashed.begin(), hashed.begin() + static_cast<long>(keep), hashed.end(), by_hash);
  hashed.resize(keep);
  Bytes bytes;
  to_bytes(hashed, bytes);
  std::vector<Pick> all = from_bytes<Pick>(group.all_gather(bytes));
  std::sort(all.begin(), all.end(), by_hash);
  all.resize(std::min(all.size(), kStarts));
  const Pick first = best_over(group, shallowest, false);
  std::vector<Vec3> starts;
  for (const Pick& p : all) starts.push_back(p.point);
  if (first.found) starts.push_back(first.point);
  return starts;
}

}  // namespace

LargePlacement place_large_first(const HeldCandidates& held, const std::vector<double>& radii,
                                 const LargeFirstSettings& s, ProcessGroup& group) {
  if (radii.empty()) return {};
  const double smallest = *std::min_element(radii.begin(), radii.end());
  std::vector<LargeCandidate> c;
  for (const LargeCandidate& q : held.points)
    if (q.depth >= smallest + s.wall_gap) c.push_back(q);
  const std::vector<Vec3> starts = spread_starts(c, radii[0] + s.wall_gap, group);
  if (starts.empty())  // the first fits nowhere: try without it
    return radii.size() < 2 ? LargePlacement{} : place_large_first(held, without_first(radii), s, group);
  return best_of(c, starts, radii, s,
                 [&group](const Pick& mine, bool farthest) { return best_over(group, mine, farthest); });
}

}  // namespace pfill
