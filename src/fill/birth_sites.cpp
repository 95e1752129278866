// Choosing birth sites from the signed distance field, and the room test.
#include "pfill/birth_sites.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

namespace pfill {

std::vector<BirthSite> choose_birth_sites(const ScalarGrid& sdf, int count, double min_depth, double depth_share) {
  std::vector<BirthSite> sites;
  size_t deepest = sdf.values.size();
  for (size_t i = 0; i < sdf.values.size(); ++i)
    if (deepest == sdf.values.size() || sdf.values[i] < sdf.values[deepest]) deepest = i;
  if (deepest == sdf.values.size() || -sdf.values[deepest] < min_depth) return sites;

  const int nx = sdf.dims[0], ny = sdf.dims[1];
  auto point = [&](size_t idx) {
    return sdf.point(static_cast<int>(idx % nx), static_cast<int>((idx / nx) % ny),
                     static_cast<int>(idx / (static_cast<size_t>(nx) * ny)));
  };
  const double max_depth = -static_cast<double>(sdf.values[deepest]);
  sites.push_back({point(deepest), max_depth});

  // The deep core, and each candidate's distance to the nearest chosen site.
  std::vector<size_t> core;
  const double floor_depth = std::max(min_depth, depth_share * max_depth);
  for (size_t i = 0; i < sdf.values.size(); ++i)
    if (-sdf.values[i] >= floor_depth) core.push_back(i);
  std::vector<double> nearest(core.size());
  for (size_t k = 0; k < core.size(); ++k) nearest[k] = length(point(core[k]) - sites[0].position);
  while (static_cast<int>(sites.size()) < count) {
    // Farthest core point whose inscribed ball does not meet another site's.
    size_t best = core.size();
    for (size_t k = 0; k < core.size(); ++k) {
      if (best != core.size() && nearest[k] <= nearest[best]) continue;
      const Vec3 p = point(core[k]);
      const double depth = -static_cast<double>(sdf.values[core[k]]);
      const bool apart = std::all_of(sites.begin(), sites.end(), [&](const BirthSite& s) {
        return length(s.position - p) >= s.depth + depth;
      });
      if (apart) best = k;
    }
    if (best == core.size()) break;  // no room for another site
    const Vec3 p = point(core[best]);
    sites.push_back({p, -static_cast<double>(sdf.values[core[best]])});
    for (size_t k = 0; k < core.size(); ++k) nearest[k] = std::min(nearest[k], length(point(core[k]) - p));
  }
  return sites;
}

bool site_has_room(const std::vector<Vec3>& centres, const std::vector<double>& radii, const Vec3& site,
                   double radius, double share) {
  for (size_t i = 0; i < centres.size(); ++i) {
    const Vec3 d = centres[i] - site;
    const double t = share * (radius + radii[i]);
    if (dot(d, d) < t * t) return false;
  }
  return true;
}

size_t pocket_capacity(const BirthSite& site, double radius) {
  if (!(radius > 0) || site.depth > kPocketDepth * radius) return 0;
  const double q = site.depth / radius;
  return static_cast<size_t>(std::max(1.0, std::floor(0.7405 * q * q * q)));
}

bool pocket_full(const std::vector<Vec3>& centres, const BirthSite& site, double radius) {
  const size_t most = pocket_capacity(site, radius);
  if (most == 0) return false;
  const double reach = site.depth - 0.5 * radius, r2 = reach * reach;
  size_t in = 0;
  for (const Vec3& p : centres) {
    const Vec3 d = p - site.position;
    if (dot(d, d) < r2 && ++in >= most) return true;
  }
  return false;
}

bool site_has_room(const std::vector<Vec3>& centres, const Vec3& site, double clearance) {
  const double c2 = clearance * clearance;
  for (const Vec3& p : centres) {
    const Vec3 d = p - site;
    if (dot(d, d) < c2) return false;
  }
  return true;
}

}  // namespace pfill

namespace pfill {

namespace {

struct SiteCandidate {
  float depth;
  size_t index;
};

// The sub-lattice's points at least `min_depth` deep, in grid order; its
// z-slices in parallel (the field of a 1e5 fill has 2^26 samples).
std::vector<SiteCandidate> deep_points(const ScalarGrid& sdf, int stride, double min_depth) {
  const int nx = sdf.dims[0], ny = sdf.dims[1], nz = sdf.dims[2];
  const int slices = (nz + stride - 1) / stride;
  std::vector<std::vector<SiteCandidate>> found(static_cast<size_t>(std::max(slices, 0)));
  tbb::parallel_for(0, slices, [&](int s) {
    const int k = s * stride;
    for (int j = 0; j < ny; j += stride)
      for (int i = 0; i < nx; i += stride) {
        const float depth = -sdf.at(i, j, k);
        if (depth >= min_depth) found[static_cast<size_t>(s)].push_back({depth, sdf.index(i, j, k)});
      }
  });
  std::vector<SiteCandidate> out;
  for (const auto& f : found) out.insert(out.end(), f.begin(), f.end());
  return out;
}

// The sites chosen so far in a dense grid of cells at least `spacing`
// wide over the field's box (a hash of cells cost a lookup per cell and
// candidate: a second of the 1e5 fill's set-up), each cell a linked list.
class ChosenSites {
 public:
  ChosenSites(const ScalarGrid& sdf, double spacing) : origin_(sdf.origin), spacing2_(spacing * spacing) {
    const Vec3 size = sdf.upper() - sdf.origin;
    constexpr double kMostCells = 1 << 22;  // wider cells past that: the query stays complete
    cell_ = std::max(spacing, std::cbrt((size.x + spacing) * (size.y + spacing) * (size.z + spacing) / kMostCells));
    for (int a = 0; a < 3; ++a) dims_[a] = static_cast<int>(size[a] / cell_) + 1;
    head_.assign(static_cast<size_t>(dims_[0]) * dims_[1] * dims_[2], kNone);
  }

  /// Whether a chosen site lies closer than the spacing to p (p in the field's box).
  bool near(const Vec3& p) const {
    const auto c = cell_of(p);
    for (int k = std::max(0, c[2] - 1); k <= std::min(dims_[2] - 1, c[2] + 1); ++k)
      for (int j = std::max(0, c[1] - 1); j <= std::min(dims_[1] - 1, c[1] + 1); ++j)
        for (int i = std::max(0, c[0] - 1); i <= std::min(dims_[0] - 1, c[0] + 1); ++i)
          for (uint32_t m = head_[index(i, j, k)]; m != kNone; m = next_[m]) {
            const Vec3 d = points_[m] - p;
            if (dot(d, d) < spacing2_) return true;
          }
    return false;
  }

  void add(const Vec3& p) {
    const auto c = cell_of(p);
    uint32_t& head = head_[index(c[0], c[1], c[2])];
    next_.push_back(head);
    head = static_cast<uint32_t>(points_.size());
    points_.push_back(p);
  }

 private:
  static constexpr uint32_t kNone = 0xffffffffu;
  std::array<int, 3> cell_of(const Vec3& p) const {
    std::array<int, 3> c{};
    for (int a = 0; a < 3; ++a) c[a] = std::clamp(static_cast<int>(std::floor((p[a] - origin_[a]) / cell_)), 0, dims_[a] - 1);
    return c;
  }
  size_t index(int i, int j, int k) const {
    return static_cast<size_t>(i) + static_cast<size_t>(dims_[0]) * (static_cast<size_t>(j) + static_cast<size_t>(dims_[1]) * k);
  }
  Vec3 origin_;
  double spacing2_, cell_ = 1;
  std::array<int, 3> dims_{1, 1, 1};
  std::vector<uint32_t> head_, next_;
  std::vector<Vec3> points_;
};

}  // namespace

std::vector<BirthSite> spread_birth_sites(const ScalarGrid& sdf, double spacing, double min_depth) {
  const int nx = sdf.dims[0], ny = sdf.dims[1];
  const int stride = std::max(1, static_cast<int>(spacing / 3 / sdf.spacing));
  std::vector<SiteCandidate> candidates = deep_points(sdf, stride, min_depth);
  // Deepest first; ties by grid index, so the choice does not depend on the sort.
  tbb::parallel_sort(candidates.begin(), candidates.end(), [](const SiteCandidate& a, const SiteCandidate& b) {
    return a.depth > b.depth || (a.depth == b.depth && a.index < b.index);
  });
  std::vector<BirthSite> sites;
  if (candidates.empty()) return sites;
  ChosenSites chosen(sdf, spacing);
  for (const SiteCandidate& c : candidates) {
    const Vec3 p = sdf.point(static_cast<int>(c.index % nx), static_cast<int>((c.index / nx) % ny),
                             static_cast<int>(c.index / (static_cast<size_t>(nx) * ny)));
    if (chosen.near(p)) continue;
    chosen.add(p);
    sites.push_back({p, c.depth});
  }
  return sites;
}

RoomGrid::RoomGrid(const std::vector<Vec3>& centres, double clearance) : clearance_(clearance) {
  if (centres.empty()) return;
  Vec3 lo = centres[0], hi = centres[0];
  for (const Vec3& p : centres) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  origin_ = lo - Vec3(1, 1, 1) * clearance;
  const Vec3 size = hi - lo + Vec3(2, 2, 2) * clearance;
  // Cells of at least the clearance, at most ~2 per centre (a sparse snapshot in a big box).
  double cell = clearance;
  const double cap = 2.0 * static_cast<double>(centres.size()) + 64;
  if (size.x / cell * (size.y / cell) * (size.z / cell) > cap) cell = std::cbrt(size.x * size.y * size.z / cap);
  cell_ = cell;
  dims_ = {static_cast<int>(size.x / cell) + 1, static_cast<int>(size.y / cell) + 1,
           static_cast<int>(size.z / cell) + 1};
  const size_t cells = static_cast<size_t>(dims_[0]) * dims_[1] * dims_[2];
  start_.assign(cells + 1, 0);
  std::vector<uint32_t> cell_of_centre(centres.size());
  for (size_t i = 0; i < centres.size(); ++i) {
    std::array<int, 3> c{};
    cell_of(centres[i], c);
    cell_of_centre[i] = static_cast<uint32_t>(cell_index(c));
    ++start_[cell_of_centre[i] + 1];
  }
  for (size_t c = 0; c < cells; ++c) start_[c + 1] += start_[c];
  sorted_.resize(centres.size());
  std::vector<uint32_t> fill(start_.begin(), start_.end() - 1);
  for (size_t i = 0; i < centres.size(); ++i) sorted_[fill[cell_of_centre[i]]++] = centres[i];
}

bool RoomGrid::cell_of(const Vec3& p, std::array<int, 3>& c) const {
  const Vec3 q = (p - origin_) / cell_;
  c = {static_cast<int>(std::floor(q.x)), static_cast<int>(std::floor(q.y)), static_cast<int>(std::floor(q.z))};
  for (int a = 0; a < 3; ++a)
    if (c[a] < 0 || c[a] >= dims_[a]) return false;
  return true;
}

RoomGrid::RoomGrid(const std::vector<Vec3>& centres, const std::vector<double>& radii, double share, double largest)
    : share_(share) {
  double widest = 0;
  for (double r : radii) widest = std::max(widest, r);
  *this = RoomGrid(centres, share * (largest + widest));
  share_ = share;
  if (centres.empty()) return;
  // The radii in the cell order of sorted_ (the build's order, again).
  radii_.resize(centres.size());
  std::vector<uint32_t> fill(start_.begin(), start_.end() - 1);
  for (size_t i = 0; i < centres.size(); ++i) {
    std::array<int, 3> c{};
    cell_of(centres[i], c);
    radii_[fill[cell_index(c)]++] = radii[i];
  }
}

bool RoomGrid::has_room(const Vec3& site) const { return has_room(site, -1); }

bool RoomGrid::has_room(const Vec3& site, double radius) const {
  const double c2 = clearance_ * clearance_;
  if (start_.empty()) return true;
  const bool unequal = !radii_.empty() && radius >= 0;
  const Vec3 q = (site - origin_) / cell_;
  const int reach = static_cast<int>(std::ceil(clearance_ / cell_));
  const int ci = static_cast<int>(std::floor(q.x)), cj = static_cast<int>(std::floor(q.y)),
            ck = static_cast<int>(std::floor(q.z));
  for (int k = std::max(0, ck - reach); k <= std::min(dims_[2] - 1, ck + reach); ++k)
    for (int j = std::max(0, cj - reach); j <= std::min(dims_[1] - 1, cj + reach); ++j)
      for (int i = std::max(0, ci - reach); i <= std::min(dims_[0] - 1, ci + reach); ++i) {
        const size_t c = cell_index({i, j, k});
        for (uint32_t m = start_[c]; m < start_[c + 1]; ++m) {
          const Vec3 d = sorted_[m] - site;
          const double t = unequal ? share_ * (radius + radii_[m]) : 0;
          if (dot(d, d) < (unequal ? t * t : c2)) return false;
        }
      }
  return true;
}

bool RoomGrid::pocket_full(const BirthSite& site, double radius) const {
  const size_t most = pocket_capacity(site, radius);
  if (most == 0 || start_.empty()) return false;
  const double reach = site.depth - 0.5 * radius, r2 = reach * reach;
  const Vec3 q = (site.position - origin_) / cell_;
  const int cells = static_cast<int>(std::ceil(reach / cell_));
  const int ci = static_cast<int>(std::floor(q.x)), cj = static_cast<int>(std::floor(q.y)),
            ck = static_cast<int>(std::floor(q.z));
  size_t in = 0;
  for (int k = std::max(0, ck - cells); k <= std::min(dims_[2] - 1, ck + cells); ++k)
    for (int j = std::max(0, cj - cells); j <= std::min(dims_[1] - 1, cj + cells); ++j)
      for (int i = std::max(0, ci - cells); i <= std::min(dims_[0] - 1, ci + cells); ++i) {
        const size_t c = cell_index({i, j, k});
        for (uint32_t m = start_[c]; m < start_[c + 1]; ++m) {
          const Vec3 d = sorted_[m] - site.position;
          if (dot(d, d) < r2 && ++in >= most) return true;
        }
      }
  return false;
}

PartSites add_sites_per_part(const ScalarGrid& sdf, double min_depth, std::vector<BirthSite>& sites) {
  PartSites out;
  const int nx = sdf.dims[0], ny = sdf.dims[1], nz = sdf.dims[2];
  const size_t n = sdf.values.size();
  if (n == 0 || static_cast<size_t>(nx) * ny * nz != n) return out;
  constexpr uint32_t kNone = 0xffffffffu;
  std::vector<uint32_t> label(n, kNone);
  std::vector<size_t> deepest;  // per part
  std::vector<size_t> stack;
  for (size_t seed = 0; seed < n; ++seed) {
    if (label[seed] != kNone || !(sdf.values[seed] < 0)) continue;
    const auto part = static_cast<uint32_t>(deepest.size());
    deepest.push_back(seed);
    label[seed] = part;
    stack.assign(1, seed);
    while (!stack.empty()) {
      const size_t c = stack.back();
      stack.pop_back();
      if (sdf.values[c] < sdf.values[deepest[part]] || (sdf.values[c] == sdf.values[deepest[part]] && c < deepest[part]))
        deepest[part] = c;
      const int i = static_cast<int>(c % nx), j = static_cast<int>((c / nx) % ny),
                k = static_cast<int>(c / (static_cast<size_t>(nx) * ny));
      const int step[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
      for (const auto& d : step) {
        const int a = i + d[0], b = j + d[1], e = k + d[2];
        if (a < 0 || b < 0 || e < 0 || a >= nx || b >= ny || e >= nz) continue;
        const size_t m = sdf.index(a, b, e);
        if (label[m] == kNone && sdf.values[m] < 0) {
          label[m] = part;
          stack.push_back(m);
        }
      }
    }
  }
  out.parts = deepest.size();
  std::vector<char> has_site(deepest.size(), 0);
  for (const BirthSite& s : sites) {
    const Vec3 q = (s.position - sdf.origin) / sdf.spacing;
    const int i = static_cast<int>(std::lround(q.x)), j = static_cast<int>(std::lround(q.y)),
              k = static_cast<int>(std::lround(q.z));
    if (i < 0 || j < 0 || k < 0 || i >= nx || j >= ny || k >= nz) continue;
    const uint32_t part = label[sdf.index(i, j, k)];
    if (part != kNone) has_site[part] = 1;
  }
  for (size_t part = 0; part < deepest.size(); ++part) {
    if (has_site[part]) continue;
    const size_t c = deepest[part];
    const double depth = -static_cast<double>(sdf.values[c]);
    if (depth < min_depth) {
      ++out.too_small;
      continue;
    }
    sites.push_back({sdf.point(static_cast<int>(c % nx), static_cast<int>((c / nx) % ny),
                               static_cast<int>(c / (static_cast<size_t>(nx) * ny))),
                     depth});
    ++out.added;
  }
  return out;
}

}  // namespace pfill
