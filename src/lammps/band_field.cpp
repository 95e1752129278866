// The wall's field in bricks, made on first use: see band_field.hpp.
#ifdef PFILL_WITH_LAMMPS
#include "lammps/band_field.hpp"
#include "lammps/fma_clones.hpp"

#include <sys/mman.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <new>

#include "../../kernels/physics_double.hpp"

namespace pfill {
namespace lammps_engine {
namespace {

constexpr size_t kChunkBytes = size_t(2) << 20;

}  // namespace

void BandField::FreeChunk::operator()(float* p) const { std::free(p); }

BandField::BandField(const ScalarGrid& field, double offset, double band)
    : field_(field), offset_(static_cast<float>(offset)), band_(band) {
  for (int a = 0; a < 3; ++a) {
    nb_[a] = (field.dims[a] - 2) / kCells + 1;  // cells 0 .. dims - 2
    ng_[a] = (nb_[a] + kGroup - 1) / kGroup;
  }
  groups_.assign(static_cast<size_t>(ng_[0]) * ng_[1] * ng_[2], kUnseen);
  const size_t count = static_cast<size_t>(nb_[0]) * nb_[1] * nb_[2];
  // The slope: at most the norm of the largest sample differences along x,
  // y, z over the spacing (every pair of neighbouring samples lies in a brick).
  double dmax[3] = {0, 0, 0};
  float v[kSide * kSide * kSide];
  for (size_t b = 0; b < count; ++b) {
    read_brick(b, v);
    float top = -INFINITY;
    for (int z = 0; z < kSide; ++z)
      for (int y = 0; y < kSide; ++y)
        for (int x = 0; x < kSide; ++x) {
          const float* s = v + x + kSide * (y + kSide * z);
          top = std::max(top, *s);
          const double s0 = s[0];
          if (x + 1 < kSide) dmax[0] = std::max(dmax[0], std::fabs(s[1] - s0));
          if (y + 1 < kSide) dmax[1] = std::max(dmax[1], std::fabs(s[kSide] - s0));
          if (z + 1 < kSide) dmax[2] = std::max(dmax[2], std::fabs(s[kSide * kSide] - s0));
        }
    int32_t& e = entry(static_cast<int>(b % nb_[0]), static_cast<int>(b / nb_[0] % nb_[1]), static_cast<int>(b / nb_[0] / nb_[1]));
    if (top > -band_) {
      e = static_cast<int32_t>(bricks_.size());
      bricks_.push_back(static_cast<int32_t>(b));
    }
  }
  lipschitz_ = 1.0001 * std::sqrt(dmax[0] * dmax[0] + dmax[1] * dmax[1] + dmax[2] * dmax[2]) / field.spacing;
  chunks_.resize((bricks_.size() + kChunkMask) >> kChunkShift);
}

BandField::BandField(const ExactField& exact, double offset, double band)
    : field_(exact.lattice()), exact_(&exact), offset_(static_cast<float>(offset)), band_(band) {
  for (int a = 0; a < 3; ++a) {
    nb_[a] = (field_.dims[a] - 2) / kCells + 1;
    ng_[a] = (nb_[a] + kGroup - 1) / kGroup;
  }
  groups_.assign(static_cast<size_t>(ng_[0]) * ng_[1] * ng_[2], kUnseen);
  // Trilinear in the samples of a 1-Lipschitz distance: each partial
  // derivative is a mean of differences of at most a spacing each.
  lipschitz_ = 1.0001 * std::sqrt(3.0);
}

BandField::~BandField() = default;

int32_t& BandField::entry(int bi, int bj, int bk) {
  int32_t& g = groups_[group_index(bi, bj, bk)];
  if (g == kUnseen) {
    g = static_cast<int32_t>(slots_.size());
    slots_.resize(slots_.size() + kGroup * kGroup * kGroup, kDeep);
  }
  return slots_[static_cast<size_t>(g) + in_group(bi, bj, bk)];
}

int32_t BandField::open_group(int bi, int bj, int bk) {
  const int g[3] = {bi / kGroup * kGroup, bj / kGroup * kGroup, bk / kGroup * kGroup};
  const double h = field_.spacing, half_diagonal = 0.5 * std::sqrt(3.0) * kCells * h;
  // The group's samples, each computed once though neighbouring bricks
  // share their faces: per sample, a bound on its distance (0: not needed).
  constexpr int kL = kGroup * kCells + 1;
  std::vector<float> values(kL * kL * kL), bound(kL * kL * kL, 0.0f);
  auto sample_index = [](int x, int y, int z) { return static_cast<size_t>(x + kL * (y + kL * z)); };
  const size_t first = bricks_.size();
  std::vector<std::array<int, 3>> corner;  // each new slot's first sample in the group's samples
  for (int z = g[2]; z < std::min(g[2] + kGroup, nb_[2]); ++z)
    for (int y = g[1]; y < std::min(g[1] + kGroup, nb_[1]); ++y)
      for (int x = g[0]; x < std::min(g[0] + kGroup, nb_[0]); ++x) {
        // (A brick past the grid's upper faces repeats their samples: its
        // clamped centre's ball still holds them.)
        const Vec3 centre = field_.point(x * kCells, y * kCells, z * kCells) + Vec3(1, 1, 1) * (0.5 * kCells * h);
        const double d = exact_->at(centre);
        int32_t& e = entry(x, y, z);
        if (d + offset_ <= -(band_ + half_diagonal)) {
          e = kDeep;
          continue;
        }
        e = static_cast<int32_t>(bricks_.size());
        bricks_.push_back(static_cast<int32_t>(brick_index(x, y, z)));
        corner.push_back({(x - g[0]) * kCells, (y - g[1]) * kCells, (z - g[2]) * kCells});
        const float reach = static_cast<float>(1.01 * (std::fabs(d) + half_diagonal));
        for (int sz = 0; sz < kSide; ++sz)
          for (int sy = 0; sy < kSide; ++sy)
            for (int sx = 0; sx < kSide; ++sx) {
              const size_t n = sample_index(corner.back()[0] + sx, corner.back()[1] + sy, corner.back()[2] + sz);
              bound[n] = std::max(bound[n], reach);
            }
      }
  std::vector<uint32_t> needed;
  for (size_t n = 0; n < bound.size(); ++n)
    if (bound[n] > 0) needed.push_back(static_cast<uint32_t>(n));
  // On this thread: a group is a few ms, and TBB's workers, spinning
  // after each, would take the core of the next MPI rank.
  for (const uint32_t m : needed) {
    const int n = static_cast<int>(m);
    values[m] = static_cast<float>(
        exact_->at(g[0] * kCells + n % kL, g[1] * kCells + n / kL % kL, g[2] * kCells + n / (kL * kL), bound[m]));
  }
  chunks_.resize((bricks_.size() + kChunkMask) >> kChunkShift);
  for (size_t slot = first; slot < bricks_.size(); ++slot) {
    std::unique_ptr<float[], FreeChunk>& c = chunks_[slot >> kChunkShift];
    if (!c) c.reset(allocate_chunk());
    float* v = c.get() + (slot & static_cast<size_t>(kChunkMask)) * kBrickFloats;
    const std::array<int, 3>& o = corner[slot - first];
    for (int z = 0; z < kSide; ++z)
      for (int y = 0; y < kSide; ++y)
        for (int x = 0; x < kSide; ++x)
          v[x + kSide * (y + kSide * z)] = values[sample_index(o[0] + x, o[1] + y, o[2] + z)] + offset_;
  }
  return entry(bi, bj, bk);
}

size_t BandField::bytes() const {
  size_t n = (groups_.size() + slots_.size() + bricks_.size()) * sizeof(int32_t);
  if (exact_) return n + bricks_.size() * kBrickFloats * sizeof(float);  // (the last chunk's rest: not yet written)
  for (const auto& c : chunks_) n += c ? kChunkBytes : 0;
  return n;
}

void BandField::read_brick(size_t b, float* v) const {
  const ScalarGrid& f = field_;
  const int bi = static_cast<int>(b % nb_[0]), bj = static_cast<int>(b / nb_[0] % nb_[1]),
            bk = static_cast<int>(b / nb_[0] / nb_[1]);
  for (int z = 0; z < kSide; ++z)
    for (int y = 0; y < kSide; ++y) {
      const int j = std::min(bj * kCells + y, f.dims[1] - 1), k = std::min(bk * kCells + z, f.dims[2] - 1);
      for (int x = 0; x < kSide; ++x)
        v[x + kSide * (y + kSide * z)] = f.at(std::min(bi * kCells + x, f.dims[0] - 1), j, k) + offset_;
    }
}

float* BandField::allocate_chunk() {
  void* p = std::aligned_alloc(kChunkBytes, kChunkBytes);
  if (!p) throw std::bad_alloc();
  madvise(p, kChunkBytes, MADV_HUGEPAGE);  // one TLB entry for 4,096 bricks, where the kernel allows
  return static_cast<float*>(p);
}

void BandField::fill_chunk(int32_t chunk) {
  float* values = allocate_chunk();
  const size_t first = static_cast<size_t>(chunk) << kChunkShift;
  for (size_t s = first; s < std::min(bricks_.size(), first + kChunkMask + 1); ++s)
    read_brick(static_cast<size_t>(bricks_[s]), values + (s - first) * kBrickFloats);
  chunks_[static_cast<size_t>(chunk)].reset(values);
}

/// pf_sdf_sample's cell and fractions at p (physics.cl), in its
/// operations; its fmin and fmax as compares (the same for the finite
/// positions the engine holds), which compile inline where fmin and fmax
/// are calls into libm.
BandField::Cell BandField::cell_at(double px, double py, double pz) const {
  const ScalarGrid& f = field_;
  const double inv = 1 / f.spacing;
  auto clamp = [](double g, double hi) { return g > 0.0 ? (g < hi ? g : hi) : 0.0; };
  const double gx = clamp((px - f.origin.x) * inv, static_cast<double>(f.dims[0] - 1));
  const double gy = clamp((py - f.origin.y) * inv, static_cast<double>(f.dims[1] - 1));
  const double gz = clamp((pz - f.origin.z) * inv, static_cast<double>(f.dims[2] - 1));
  Cell c;
  c.i = std::min(static_cast<int>(std::floor(gx)), f.dims[0] - 2);
  c.j = std::min(static_cast<int>(std::floor(gy)), f.dims[1] - 2);
  c.k = std::min(static_cast<int>(std::floor(gz)), f.dims[2] - 2);
  c.tx = gx - c.i, c.ty = gy - c.j, c.tz = gz - c.k;
  return c;
}

PFILL_FMA_CLONES bool BandField::sample_unless_deep(double px, double py, double pz, double* g, double& phi,
                                                    int32_t& slot) {
  const Cell c = cell_at(px, py, pz);
  const int32_t b = brick(c.i, c.j, c.k);
  if (b == kDeep) return false;
  slot = b;
  const float* s = corners(c, b);
  constexpr int sy = kSide, sz = kSide * kSide;
  phi = physics::pf_trilinear(s[0], s[1], s[sy], s[sy + 1], s[sz], s[sz + 1], s[sy + sz], s[sy + sz + 1], c.tx, c.ty,
                              c.tz, 1 / field_.spacing, g);
  return true;
}

PFILL_FMA_CLONES double BandField::sample(double px, double py, double pz, double* g) {
  double phi = 0;
  int32_t slot = 0;
  if (sample_unless_deep(px, py, pz, g, phi, slot)) return phi;
  // (the wall's push never samples so deep; exact all the same)
  const Cell c = cell_at(px, py, pz);
  double v[8];
  for (int n = 0; n < 8; ++n) {
    const int i = c.i + (n & 1), j = c.j + ((n >> 1) & 1), k = c.k + ((n >> 2) & 1);
    v[n] = (exact_ ? static_cast<float>(exact_->at(i, j, k)) : field_.at(i, j, k)) + offset_;
  }
  return physics::pf_trilinear(v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], c.tx, c.ty, c.tz, 1 / field_.spacing,
                               g);
}

PFILL_FMA_CLONES void BandField::prefetch(double px, double py, double pz, int32_t slot) const {
  if (slot < 0 || static_cast<size_t>(slot) >= bricks_.size() || !chunks_[static_cast<size_t>(slot >> kChunkShift)])
    return;
  const Cell c = cell_at(px, py, pz);  // (in another brick since: a useless hint, no harm)
  const float* s = chunks_[static_cast<size_t>(slot >> kChunkShift)].get() + (slot & kChunkMask) * kBrickFloats +
                   (c.i % kCells) + kSide * ((c.j % kCells) + kSide * (c.k % kCells));
  __builtin_prefetch(s);
  __builtin_prefetch(s + kSide * kSide + kSide + 1);
}

}  // namespace lammps_engine
}  // namespace pfill
#endif
