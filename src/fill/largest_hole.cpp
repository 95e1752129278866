// The largest empty hole of a packing inside a mesh, by exact distances
// (packing_metrics.hpp: largest_hole): grid points at r / 2 near the
// spheres, largest gap first, checked for depth with the boundary, then the
// best few climbed to their hole's centre.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <queue>
#include <tuple>

#include <tbb/parallel_for.h>

#include "fill/centre_grid.hpp"
#include "fill/depth_test.hpp"
#include "fill/hole_climb.hpp"
#include "pfill/error.hpp"
#include "pfill/packing_metrics.hpp"
#include "pfill/particle_share.hpp"

namespace pfill {
namespace {

/// The spheres by size, in levels of radius doublings (unequal spheres;
/// equal ones make one level): each level's grid is as coarse as its own
/// largest sphere's reach, 2 r + its radius, so a search among small
/// spheres no longer reads the cells a 1:10 mix's largest would need (at
/// 1:10 a grid for the largest reach held ~6,700 small spheres in the 27
/// cells around a point; the hole search took most of the verify).
struct SizeLevel {
  std::vector<Vec3> centres;
  std::vector<double> radii;
  double reach = 0;  ///< 2 r + the level's largest radius: beyond it a sphere leaves the gap at its 2 r cap
  CentreGrid grid{1.0};
};

std::vector<SizeLevel> size_levels(const ParticleSet& particles, double radius) {
  constexpr int kMaxLevels = 8;
  double smallest = particles.radii.front();
  for (double r : particles.radii) smallest = std::min(smallest, r);
  std::vector<SizeLevel> levels(kMaxLevels);
  for (size_t i = 0; i < particles.size(); ++i) {
    const int l = std::min(kMaxLevels - 1, static_cast<int>(std::floor(std::log2(particles.radii[i] / smallest))));
    SizeLevel& level = levels[static_cast<size_t>(std::max(0, l))];
    level.centres.push_back(particles.positions[i]);
    level.radii.push_back(particles.radii[i]);
    level.reach = std::max(level.reach, 2 * radius + particles.radii[i]);
  }
  levels.erase(std::remove_if(levels.begin(), levels.end(), [](const SizeLevel& l) { return l.centres.empty(); }),
               levels.end());
  for (SizeLevel& level : levels) level.grid = CentreGrid(level.centres, level.reach);
  return levels;
}

class HoleSearch {
 public:
  /// `within`: grid points only in this box (a process's region; null: everywhere).
  HoleSearch(const Boundary& boundary, const ParticleSet& particles, double radius, const Box3* within)
      : radius_(radius), h_(0.5 * radius), levels_(size_levels(particles, radius)) {
    for (const SizeLevel& level : levels_) reach_ = std::max(reach_, level.reach);
    Box3 box;
    for (const Vec3& c : particles.positions) box.add(c);
    lo_ = box.lo - Vec3(reach_, reach_, reach_);
    Vec3 span = box.hi - box.lo + Vec3(2 * reach_, 2 * reach_, 2 * reach_);
    if (within) {
      lo_ = max(lo_, within->lo);
      span = min(box.hi + Vec3(reach_, reach_, reach_), within->hi) - lo_;
    }
    for (int a = 0; a < 3; ++a) n_[a] = std::max(1, static_cast<int>(std::ceil(span[a] / h_)) + 1);
    if (static_cast<uint64_t>(std::max({n_[0], n_[1], n_[2]})) > kAxis)
      throw Error("largest hole: the packing spans more than 2^21 grid points of r / 2 along an axis");
    depth_ = std::make_unique<DepthTest>(boundary, radius, lo_, h_);
  }

  Hole run() {
    // Only the points within h of the best decide (the batches stop below
    // that, the seeds too): first those over a floor, which holds them
    // whenever the best lies more than h above it (nearly always: a
    // packing's largest hole is ~0.9 r); else, all of them, as the floor
    // may have hidden a deeper or a closer one. The same answer either way.
    const double floor_gap = 0.2 * radius_;
    search(collect(floor_gap));
    if (!(best_ - h_ > floor_gap)) search(collect(0));
    climb_best();
    return {best_at_, best_ / radius_};
  }

  /// run()'s hole first, then the other distinct holes its climb found
  /// (those within a grid step of the best), widest first.
  std::vector<Hole> run_all() {
    std::vector<Hole> out{run()};
    for (const Hole& c : climbed_)
      if (length(c.centre - out.front().centre) >= radius_) out.push_back(c);
    std::stable_sort(out.begin() + 1, out.end(), [](const Hole& a, const Hole& b) { return a.gap_over_r > b.gap_over_r; });
    return out;
  }

 private:
  // A candidate is 16 bytes (its gap and its grid index; its point is
  // recomputed): over no floor there are ~20 a sphere, which at 32 bytes
  // made 0.6 GiB at 1e6 spheres.
  struct Candidate {
    double gap;
    uint64_t at;  // i | j << 21 | k << 42
  };
  static constexpr uint64_t kAxis = (uint64_t(1) << 21) - 1;

  /// Distance from p to the nearest sphere's surface (reach - r when none is in reach).
  double gap(const Vec3& p) const {
    double g = 2 * radius_;  // (holes over 2 r count as 2 r)
    for (const SizeLevel& l : levels_)
      l.grid.for_near(p, [&](uint32_t i) { g = std::min(g, length(l.centres[i] - p) - l.radii[i]); });
    return g;
  }

  /// gap(p) where p lies within some sphere's reach (its level's; elsewhere
  /// the gap is at its cap and p no candidate) and the gap exceeds `floor`;
  /// else a value at most `floor`. The scan stops at the first sphere within
  /// the floor (most grid points lie in a sphere): a 1e5 fill's search read
  /// every sphere near each of its ~10^7 points. The same gaps as gap().
  double gap_above(const Vec3& p, double floor) const {
    double g = 2 * radius_;
    bool near = false;
    for (const SizeLevel& l : levels_) {
      const bool below = l.grid.any_near(p, [&](uint32_t i) {
        const double d = length(l.centres[i] - p);
        near = near || d < l.reach;
        g = std::min(g, d - l.radii[i]);
        return g <= floor;
      });
      if (below) return g;
    }
    return near ? g : floor;
  }

  /// At least r inside, by exact distance (points outside the mesh fail).
  bool deep(const Vec3& p) const { return depth_->deep(p); }

  Vec3 point(uint64_t at) const {
    return lo_ + Vec3(static_cast<double>(at & kAxis), static_cast<double>((at >> 21) & kAxis),
                      static_cast<double>(at >> 42)) * h_;
  }

  /// One bit a grid point, set from several threads.
  struct Bits {
    std::unique_ptr<std::atomic<uint64_t>[]> words;
    bool test(uint64_t n) const { return words && (words[n >> 6].load(std::memory_order_relaxed) >> (n & 63)) & 1; }
    void set(uint64_t n) { words[n >> 6].fetch_or(uint64_t(1) << (n & 63), std::memory_order_relaxed); }
  };
  uint64_t grid_index(int i, int j, int k) const {
    return static_cast<uint64_t>(i) + static_cast<uint64_t>(n_[0]) * (static_cast<uint64_t>(j) + static_cast<uint64_t>(n_[1]) * k);
  }

  /// The grid points some sphere's surface lies within `floor_gap` of (by
  /// the expression gap_above() reads): each sphere marks the few points
  /// of its own box (~60 at r / 2), where gap_above() would scan the 27
  /// cells around each point until it met that sphere. None past 2^33 points.
  Bits covered_points(double floor_gap) const {
    Bits bits;
    const uint64_t points = static_cast<uint64_t>(n_[0]) * static_cast<uint64_t>(n_[1]) * static_cast<uint64_t>(n_[2]);
    if (points > (uint64_t(1) << 33)) return bits;
    bits.words.reset(new std::atomic<uint64_t>[points / 64 + 1]());
    for (const SizeLevel& l : levels_)
      tbb::parallel_for(size_t(0), l.centres.size(), [&](size_t s) {
        const Vec3& c = l.centres[s];
        const double reach = l.radii[s] + floor_gap;
        int from[3], to[3];
        for (int a = 0; a < 3; ++a) {  // (a point of margin against rounding: the test below decides)
          from[a] = std::max(0, static_cast<int>(std::floor((c[a] - reach - lo_[a]) / h_)) - 1);
          to[a] = std::min(n_[a] - 1, static_cast<int>(std::ceil((c[a] + reach - lo_[a]) / h_)) + 1);
        }
        for (int k = from[2]; k <= to[2]; ++k)
          for (int j = from[1]; j <= to[1]; ++j)
            for (int i = from[0]; i <= to[0]; ++i)
              if (length(c - (lo_ + Vec3(i, j, k) * h_)) - l.radii[s] <= floor_gap) bits.set(grid_index(i, j, k));
      });
    return bits;
  }

  /// The candidates' one order: the largest gap first, ties by place.
  bool before(const Candidate& a, const Candidate& b) const {
    if (a.gap != b.gap) return a.gap > b.gap;
    const Vec3 pa = point(a.at), pb = point(b.at);
    return std::tie(pa.x, pa.y, pa.z) < std::tie(pb.x, pb.y, pb.z);
  }

  /// Grid points near the spheres with room beyond `floor_gap`, a vector a
  /// z-slice (found and sorted in parallel), each in before()'s order.
  using Slices = std::vector<std::vector<Candidate>>;
  Slices collect(double floor_gap) const {
    const Bits covered = covered_points(floor_gap);
    Slices slices(static_cast<size_t>(n_[2]));
    tbb::parallel_for(0, n_[2], [&](int k) {
      std::vector<Candidate>& slice = slices[static_cast<size_t>(k)];
      for (int j = 0; j < n_[1]; ++j)
        for (int i = 0; i < n_[0]; ++i) {
          if (covered.test(grid_index(i, j, k))) continue;  // (gap_above would say so, after a longer scan)
          const double g = gap_above(lo_ + Vec3(i, j, k) * h_, floor_gap);
          if (g > floor_gap)
            slice.push_back(
                {g, static_cast<uint64_t>(i) | static_cast<uint64_t>(j) << 21 | static_cast<uint64_t>(k) << 42});
        }
      std::sort(slice.begin(), slice.end(), [&](const Candidate& a, const Candidate& b) { return before(a, b); });
      slice.shrink_to_fit();
    });
    return slices;
  }

  /// The largest gaps first, each checked for depth with exact distances,
  /// until no unchecked point can beat the best. The slices are merged as
  /// they are read (a heap of their heads): the order of one sort of every
  /// candidate, without a copy of them all (unequal spheres' verify held
  /// both, 31 of its 76 MB at spot -n 4000 lognormal), and the search
  /// stops after the first few batches.
  void search(const Slices& slices) {
    best_ = 0;
    best_at_ = Vec3();
    accepted_.clear();
    using Head = std::pair<size_t, size_t>;  // (slice, place in it)
    auto later = [&](const Head& a, const Head& b) {
      return before(slices[b.first][b.second], slices[a.first][a.second]);
    };
    std::priority_queue<Head, std::vector<Head>, decltype(later)> heads(later);
    for (size_t k = 0; k < slices.size(); ++k)
      if (!slices[k].empty()) heads.push({k, 0});
    constexpr size_t kBatch = 4096;
    std::vector<Candidate> batch;
    std::vector<Vec3> points;
    while (!heads.empty() && slices[heads.top().first][heads.top().second].gap > best_ - h_) {
      batch.clear();
      while (batch.size() < kBatch && !heads.empty()) {
        const Head h = heads.top();
        heads.pop();
        batch.push_back(slices[h.first][h.second]);
        if (h.second + 1 < slices[h.first].size()) heads.push({h.first, h.second + 1});
      }
      points.resize(batch.size());
      for (size_t c = 0; c < batch.size(); ++c) points[c] = point(batch[c].at);
      const std::vector<uint8_t> ok = depth_->deep(points);
      for (size_t c = 0; c < batch.size(); ++c)
        if (ok[c]) {
          if (batch[c].gap > best_) {
            best_ = batch[c].gap;
            best_at_ = points[c];
          }
          accepted_.push_back(batch[c]);
        }
    }
  }

  /// Climbs from the best grid points (distinct holes) to the local maximum
  /// of the gap, staying at least r deep: the grid misses up to 0.43 r.
  void climb_best() {
    std::vector<Vec3> seeds;
    for (const Candidate& c : accepted_) {
      if (c.gap < best_ - h_ || seeds.size() >= 64) break;
      const Vec3 p = point(c.at);
      bool seen = false;
      for (const Vec3& s : seeds) seen = seen || length(s - p) < radius_;
      if (!seen) seeds.push_back(p);
    }
    std::vector<double> climbed(seeds.size(), 0);
    std::vector<Vec3> climbed_to(seeds.size());
    tbb::parallel_for(size_t(0), seeds.size(), [&](size_t k) {
      Vec3 p = seeds[k];
      climbed[k] = climb_to_hole_centre(
          p, 0.5 * h_, 0.002 * radius_, [&](const Vec3& q) { return gap(q); }, [&](const Vec3& q) { return deep(q); });
      climbed_to[k] = p;
    });
    climbed_.clear();
    for (size_t k = 0; k < climbed.size(); ++k) climbed_.push_back({climbed_to[k], climbed[k] / radius_});
    for (size_t k = 0; k < climbed.size(); ++k)
      if (climbed[k] > best_) {
        best_ = climbed[k];
        best_at_ = climbed_to[k];
      }
  }

  std::unique_ptr<DepthTest> depth_;  ///< (its corners' values kept from batch to batch)
  double radius_, h_;  ///< h: the grid's spacing
  double reach_ = 0;   ///< the largest level's reach: the search box's margin
  std::vector<SizeLevel> levels_;
  Vec3 lo_;
  int n_[3] = {0, 0, 0};
  double best_ = 0;
  Vec3 best_at_;
  std::vector<Candidate> accepted_;
  std::vector<Hole> climbed_;  ///< each seed's hole, in units of r
};

}  // namespace

Hole largest_hole(const Boundary& boundary, const ParticleSet& particles, double radius) {
  if (particles.size() == 0 || !(radius > 0)) return {};
  return HoleSearch(boundary, particles, radius, nullptr).run();
}

std::vector<Hole> largest_holes(const Boundary& boundary, const ParticleSet& particles, double radius) {
  if (particles.size() == 0 || !(radius > 0)) return {Hole{}};
  return HoleSearch(boundary, particles, radius, nullptr).run_all();
}

std::vector<Hole> largest_holes(const Boundary& boundary, const ParticleSet& own, double radius,
                                const ParticleShare& share) {
  if (share.complete()) return largest_holes(boundary, own, radius);
  // The halo: every sphere a gap in the region reads (its level's reach,
  // 2 r + its radius), and as far again for the climbs out of it.
  double largest = 0;
  for (double r : own.radii) largest = std::max(largest, r);
  const ParticleSet view = own_and_halo(own, halo_of(share, own, 2 * (2 * radius + share.group->max(largest))));
  std::vector<Hole> mine;
  if (view.size() > 0 && radius > 0) mine = HoleSearch(boundary, view, radius, share.mine()).run_all();
  if (!mine.empty() && mine.front().gap_over_r <= 0) mine.clear();  // (no point of the region was deep enough)
  std::vector<Hole> all = from_bytes<Hole>([&] {
    Bytes b;
    to_bytes(mine, b);
    return share.group->all_gather(b);
  }());
  // Widest first (ties: in process order), each a radius from any wider.
  std::stable_sort(all.begin(), all.end(), [](const Hole& a, const Hole& b) { return a.gap_over_r > b.gap_over_r; });
  std::vector<Hole> out;
  for (const Hole& h : all) {
    bool near = false;
    for (const Hole& o : out) near = near || length(o.centre - h.centre) < radius;
    if (!near) out.push_back(h);
  }
  if (out.empty()) out.push_back(Hole{});
  return out;
}

}  // namespace pfill
