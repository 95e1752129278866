// Birth sites chosen per process (site_choice.hpp).
#include "fill/site_choice.hpp"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "pfill/error.hpp"

namespace pfill {

SiteLattice::SiteLattice(const Box3& box, double spacing_, double min_depth_)
    : origin(box.lo), spacing(spacing_), min_depth(min_depth_), step(spacing_ / 3) {
  if (!(step > 0) || !std::isfinite(step)) throw Error("birth sites: the spacing must be a positive number");
  for (int a = 0; a < 3; ++a) points[a] = static_cast<int64_t>(std::floor(box.size()[a] / step)) + 2;  // past the box
}

Vec3 SiteLattice::point(uint64_t index) const {
  const auto nx = static_cast<uint64_t>(points[0]), ny = static_cast<uint64_t>(points[1]);
  return point({static_cast<int64_t>(index % nx), static_cast<int64_t>((index / nx) % ny),
                static_cast<int64_t>(index / (nx * ny))});
}

Box3 SiteLattice::extent_near(const std::vector<Box3>& regions, int region, double margin) const {
  Box3 box;
  box.add(origin);
  box.add(point({points[0] - 1, points[1] - 1, points[2] - 1}));
  if (regions.empty()) return box;
  const Box3& mine = regions[static_cast<size_t>(region)];
  const Vec3 m(margin, margin, margin);
  box.lo = max(box.lo, mine.lo - m);
  box.hi = min(box.hi, mine.hi + m);
  return box;
}

namespace {

constexpr int kBlock = 6;  // lattice points along a block's side: depths are asked block by block

// The points of a block at least min_depth inside, by their exact depth.
// The block's centre bounds every point's distance (the distance is
// 1-Lipschitz): a block wholly outside, or nowhere deep enough, asks
// nothing more; the others ask each point with that bound, which only
// speeds the search.
std::vector<DeepPoint> deep_points(const Boundary& boundary, const SiteLattice& l, const std::array<int64_t, 3>& lo,
                              const std::array<int64_t, 3>& hi) {
  std::vector<DeepPoint> out;
  Vec3 centre;
  double reach2 = 0;
  for (int a = 0; a < 3; ++a) {
    const double half = 0.5 * static_cast<double>(hi[a] - lo[a]) * l.step;
    (a == 0 ? centre.x : a == 1 ? centre.y : centre.z) = l.origin[a] + static_cast<double>(lo[a]) * l.step + half;
    reach2 += half * half;
  }
  const double reach = std::sqrt(reach2);
  const double at_centre = boundary.fast_signed_distance(centre);
  if (at_centre > reach || -at_centre + reach < l.min_depth) return out;
  for (int64_t k = lo[2]; k <= hi[2]; ++k)
    for (int64_t j = lo[1]; j <= hi[1]; ++j)
      for (int64_t i = lo[0]; i <= hi[0]; ++i) {
        const Vec3 p = l.point({i, j, k});
        const double bound = (std::fabs(at_centre) + length(p - centre)) * (1 + 1e-9) + 1e-12;
        const double depth = -boundary.fast_signed_distance(p, bound);
        if (depth >= l.min_depth) out.push_back({depth, l.index({i, j, k})});
      }
  return out;
}

}  // namespace

std::vector<std::vector<DeepPoint>> deep_points_in(const Boundary& boundary, const SiteLattice& lattice,
                                                   const Box3& box) {
  std::array<int64_t, 3> lo{}, blocks{};
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::clamp(static_cast<int64_t>(std::floor((box.lo[a] - lattice.origin[a]) / lattice.step)), int64_t{0},
                       lattice.points[a] - 1);
    const int64_t hi = std::clamp(static_cast<int64_t>(std::ceil((box.hi[a] - lattice.origin[a]) / lattice.step)),
                                  int64_t{0}, lattice.points[a] - 1);
    blocks[a] = std::max<int64_t>(0, hi - lo[a] + 1 + kBlock - 1) / kBlock;
  }
  const size_t count = static_cast<size_t>(blocks[0] * blocks[1] * blocks[2]);
  std::vector<std::vector<DeepPoint>> found(count);
  tbb::parallel_for(size_t(0), count, [&](size_t n) {
    const int64_t m = static_cast<int64_t>(n);
    const std::array<int64_t, 3> b{m % blocks[0], (m / blocks[0]) % blocks[1], m / (blocks[0] * blocks[1])};
    std::array<int64_t, 3> from{}, to{};
    for (int a = 0; a < 3; ++a) {
      from[a] = lo[a] + b[a] * kBlock;
      to[a] = std::min(from[a] + kBlock - 1, lattice.points[a] - 1);
    }
    found[n] = deep_points(boundary, lattice, from, to);
  });
  return found;
}

SiteChoice::SiteChoice(const Boundary& boundary, const SiteLattice& lattice, const std::vector<Box3>& regions,
                       int region)
    : lattice_(lattice) {
  // The lattice points within the spacing of this region (all of them for one process).
  const bool one = regions.empty();
  const Box3 grown = lattice.extent_near(regions, region, lattice.spacing);
  for (int a = 0; a < 3; ++a)
    grid_dims_[a] = std::max<int64_t>(1, static_cast<int64_t>((grown.hi[a] - grown.lo[a]) / lattice.spacing) + 1);
  grid_origin_ = grown.lo;
  const std::vector<std::vector<DeepPoint>> found = deep_points_in(boundary, lattice, grown);

  // Own, halo (the others' within the spacing of this region), or neither.
  for (const std::vector<DeepPoint>& f : found)
    for (const DeepPoint& d : f) {
      const Vec3 p = lattice.point(d.lattice);
      if (one) {
        cands_.push_back({d.depth, d.lattice, kUndecided, true, false, false, 0});
        continue;
      }
      const int owner = owning_region(regions, p);
      const bool own = owner == region;
      if (!own && distance_to_box(regions[static_cast<size_t>(region)], p) >= lattice.spacing) continue;
      bool border = false;
      for (size_t r = 0; own && r < regions.size() && !border; ++r)
        border = static_cast<int>(r) != region && distance_to_box(regions[r], p) < lattice.spacing;
      cands_.push_back({d.depth, d.lattice, kUndecided, own, border, false, 0});
    }
  std::sort(cands_.begin(), cands_.end(), [](const Candidate& a, const Candidate& b) {
    return a.depth > b.depth || (a.depth == b.depth && a.lattice < b.lattice);
  });
  const size_t cells = static_cast<size_t>(grid_dims_[0] * grid_dims_[1] * grid_dims_[2]);
  kept_.resize(cells);
  waiting_.resize(cells);
  for (size_t i = 0; i < cands_.size(); ++i) {
    const auto k = static_cast<uint32_t>(i);
    if (cands_[i].own) {
      open_.push_back(k);
      continue;
    }
    halo_.emplace(cands_[i].lattice, k);
    cands_[i].waits = true;  // until its owner says
    waiting_[cell_of(lattice_.point(cands_[i].lattice))].push_back(k);
  }
}

size_t SiteChoice::cell_of(const Vec3& p) const {
  std::array<int64_t, 3> c{};
  for (int a = 0; a < 3; ++a)
    c[a] = std::clamp(static_cast<int64_t>(std::floor((p[a] - grid_origin_[a]) / lattice_.spacing)), int64_t{0},
                      grid_dims_[a] - 1);
  return static_cast<size_t>(c[0] + grid_dims_[0] * (c[1] + grid_dims_[1] * c[2]));
}

namespace {

// Calls f(cell) for the cells of `dims` around cell `c` (itself included)
// until f returns true; whether one did.
template <class F>
bool around(const std::array<int64_t, 3>& dims, size_t c, const F& f) {
  const auto n = static_cast<int64_t>(c);
  const int64_t ci = n % dims[0], cj = (n / dims[0]) % dims[1], ck = n / (dims[0] * dims[1]);
  for (int64_t k = std::max<int64_t>(0, ck - 1); k <= std::min(dims[2] - 1, ck + 1); ++k)
    for (int64_t j = std::max<int64_t>(0, cj - 1); j <= std::min(dims[1] - 1, cj + 1); ++j)
      for (int64_t i = std::max<int64_t>(0, ci - 1); i <= std::min(dims[0] - 1, ci + 1); ++i)
        if (f(static_cast<size_t>(i + dims[0] * (j + dims[1] * k)))) return true;
  return false;
}

}  // namespace

/// Whether a kept candidate lies within the spacing of p.
bool SiteChoice::near_kept(const Vec3& p) const {
  const double s2 = lattice_.spacing * lattice_.spacing;
  return around(grid_dims_, cell_of(p), [&](size_t cell) {
    for (const Vec3& k : kept_[cell]) {
      const Vec3 d = k - p;
      if (dot(d, d) < s2) return true;
    }
    return false;
  });
}

constexpr uint32_t kNone = 0xffffffffu;

/// An undecided candidate deeper than candidate i within the spacing of p
/// (its place), or kNone; drops the decided ones from the cells it reads.
uint32_t SiteChoice::deeper_undecided(const Vec3& p, uint32_t i) {
  const double s2 = lattice_.spacing * lattice_.spacing;
  uint32_t found = kNone;
  around(grid_dims_, cell_of(p), [&](size_t cell) {
    std::vector<uint32_t>& w = waiting_[cell];
    for (size_t n = 0; n < w.size();) {
      const uint32_t m = w[n];
      if (cands_[m].state != kUndecided) {
        cands_[m].waits = false;
        w[n] = w.back();
        w.pop_back();
        continue;
      }
      ++n;
      if (m >= i) continue;  // not deeper
      const Vec3 d = lattice_.point(cands_[m].lattice) - p;
      if (dot(d, d) < s2) {
        found = m;
        return true;
      }
    }
    return false;
  });
  return found;
}

std::vector<uint64_t> SiteChoice::sweep() {
  std::vector<uint64_t> told;
  std::vector<uint32_t> still;
  for (const uint32_t i : open_) {
    Candidate& c = cands_[i];
    const Vec3 p = lattice_.point(c.lattice);
    // (A kept candidate within the spacing is always the deeper: none is
    // kept while a deeper one near it is undecided.) One still waiting for
    // the neighbour it waited for costs no search.
    if (near_kept(p)) {
      c.state = kDropped;
    } else if ((c.waits && cands_[c.blocker].state == kUndecided) || (c.blocker = deeper_undecided(p, i)) != kNone) {
      if (!c.waits) waiting_[cell_of(p)].push_back(i);  // (the deeper of this sweep are met first)
      c.waits = true;
      still.push_back(i);
      continue;
    } else {
      c.state = kKept;
      kept_[cell_of(p)].push_back(p);
    }
    if (c.border) told.push_back(c.lattice * 2 + (c.state == kKept ? 1 : 0));
  }
  open_ = std::move(still);
  return told;
}

void SiteChoice::apply(const std::vector<uint64_t>& words) {
  for (uint64_t w : words) {
    const auto it = halo_.find(w >> 1);
    if (it == halo_.end()) continue;
    Candidate& c = cands_[it->second];
    if (c.state != kUndecided) continue;
    c.state = (w & 1) ? kKept : kDropped;
    if (c.state == kKept) {
      const Vec3 p = lattice_.point(c.lattice);
      kept_[cell_of(p)].push_back(p);
    }
  }
}

std::vector<KeyedSite> SiteChoice::sites(uint64_t key_base) const {
  std::vector<KeyedSite> out;
  for (const Candidate& c : cands_)
    if (c.own && c.state == kKept) out.push_back({{lattice_.point(c.lattice), c.depth}, key_base + c.lattice});
  std::sort(out.begin(), out.end(), [](const KeyedSite& a, const KeyedSite& b) { return a.key < b.key; });
  return out;
}

std::vector<KeyedSite> choose_sites(const Boundary& boundary, const SiteLattice& lattice, const BirthView& view,
                                    ParticleEngine& engine, uint64_t key_base) {
  SiteChoice choice(boundary, lattice, view.regions, view.region);
  // Each process's decisions and, in the same gather, its count still
  // undecided (a word with the top bit set: decisions stay below 2^63).
  constexpr uint64_t kCount = uint64_t(1) << 63;
  for (;;) {
    std::vector<uint64_t> told = choice.sweep();
    if (view.complete()) break;  // one process: one sweep decides every candidate
    told.push_back(kCount | choice.undecided());
    engine.gather_over_processes(told);
    uint64_t left = 0;
    for (uint64_t w : told) left += (w & kCount) ? w & ~kCount : 0;
    told.erase(std::remove_if(told.begin(), told.end(), [](uint64_t w) { return (w & kCount) != 0; }), told.end());
    choice.apply(told);
    if (left == 0) break;
  }
  if (choice.undecided() != 0) throw Error("birth sites: a candidate was left undecided (internal error)");
  return choice.sites(key_base);
}

}  // namespace pfill
