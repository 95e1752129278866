// Rare large spheres placed before pass 1 (large_first.hpp).
#include "fill/large_first.hpp"

#include <algorithm>
#include <limits>

namespace pfill {
namespace {

// Candidate points: the field's samples on a sub-lattice about this share
// of the smallest radius apart (finer gains little: a sphere's room is
// decided within a few spacings), and the first sphere tried at this many
// starts spread over its points.
constexpr double kLattice = 1.0 / 8;
constexpr size_t kStarts = 64;

struct Candidate {
  Vec3 point;
  double depth;
};

std::vector<Candidate> candidates(const ScalarGrid& field, double min_depth) {
  const int stride = std::max(1, static_cast<int>(kLattice * min_depth / field.spacing));
  std::vector<Candidate> out;
  for (int k = 0; k < field.dims[2]; k += stride)
    for (int j = 0; j < field.dims[1]; j += stride)
      for (int i = 0; i < field.dims[0]; i += stride) {
        const double depth = -static_cast<double>(field.at(i, j, k));
        if (depth >= min_depth) out.push_back({field.point(i, j, k), depth});
      }
  return out;
}

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
Attempt place_from(const std::vector<Candidate>& c, size_t start, const std::vector<double>& radii,
                   const LargeFirstSettings& s, bool farthest) {
  Attempt a;
  // gap[p]: the least of |p - c_j| - r_j over the spheres placed so far.
  std::vector<double> gap(c.size(), std::numeric_limits<double>::infinity());
  auto put = [&](size_t p, double r) {
    a.placed.centres.push_back(c[p].point);
    a.placed.radii.push_back(r);
    for (size_t q = 0; q < c.size(); ++q) gap[q] = std::min(gap[q], length(c[q].point - c[p].point) - r);
  };
  put(start, radii[0]);
  for (size_t i = 1; i < radii.size(); ++i) {
    size_t best = c.size();
    for (size_t q = 0; q < c.size(); ++q)
      if (c[q].depth >= radii[i] + s.wall_gap && gap[q] >= radii[i] + s.pair_gap &&
          (best == c.size() || (farthest ? gap[q] > gap[best] : c[q].depth < c[best].depth)))
        best = q;
    if (best == c.size()) continue;  // no room for this one; a smaller one may still fit
    a.slack = std::min(a.slack == -std::numeric_limits<double>::infinity() ? gap[best] : a.slack,
                       gap[best] - radii[i] - s.pair_gap);
    put(best, radii[i]);
  }
  return a;
}

}  // namespace

LargePlacement place_large_first(const ScalarGrid& field, const std::vector<double>& radii,
                                 const LargeFirstSettings& s) {
  if (radii.empty()) return {};
  const double smallest = *std::min_element(radii.begin(), radii.end());
  const std::vector<Candidate> c = candidates(field, smallest + s.wall_gap);
  std::vector<size_t> first;  // the first sphere's points
  for (size_t q = 0; q < c.size(); ++q)
    if (c[q].depth >= radii[0] + s.wall_gap) first.push_back(q);
  Attempt best;
  if (first.empty()) {  // the first does not fit: try without it
    if (radii.size() < 2) return {};
    return place_large_first(field, std::vector<double>(radii.begin() + 1, radii.end()), s);
  }
  // Starts: spread over the first sphere's points, and its shallowest.
  std::vector<size_t> starts;
  for (size_t k = 0; k < first.size(); k += std::max<size_t>(1, first.size() / kStarts)) starts.push_back(first[k]);
  starts.push_back(*std::min_element(first.begin(), first.end(), [&](size_t a, size_t b) { return c[a].depth < c[b].depth; }));
  for (size_t start : starts) {
    for (bool farthest : {true, false}) {
      Attempt a = place_from(c, start, radii, s, farthest);
      if (a.better_than(best)) best = std::move(a);
    }
    if (best.placed.centres.size() == radii.size()) break;  // all fit
  }
  return best.placed;
}

}  // namespace pfill
