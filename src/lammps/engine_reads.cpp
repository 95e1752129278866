// The LAMMPS engine's reads: see engine_reads.hpp.
#ifdef PFILL_WITH_LAMMPS
#include "lammps/engine_reads.hpp"

#include <algorithm>
#include <unordered_set>
#include <utility>

#include "lammps/atom_indices.hpp"

namespace pfill {
namespace lammps_engine {
namespace {

/// The indices below `count` that no rank's atom holds (LAMMPS dropped
/// them past its box), by a bitmap over the ranks a piece at a time, so
/// that no rank holds one of every particle.
std::vector<size_t> missing_indices(const LammpsSession& lmp, size_t count) {
  constexpr size_t kPiece = size_t{1} << 24;  // indices a piece (2 MiB of bits)
  const std::vector<std::pair<size_t, int>> own = own_by_index(lmp);
  std::vector<size_t> missing;
  auto next = own.begin();
  for (size_t lo = 0; lo < count; lo += kPiece) {
    const size_t n = std::min(kPiece, count - lo);
    std::vector<uint64_t> bits((n + 63) / 64, 0);
    for (; next != own.end() && next->first < lo + n; ++next) {
      const size_t k = next->first - lo;
      bits[k / 64] |= uint64_t{1} << (k % 64);
    }
    if (lmp.ranks() > 1)
      MPI_Allreduce(MPI_IN_PLACE, bits.data(), static_cast<int>(bits.size()), MPI_UINT64_T, MPI_BOR, lmp.comm());
    for (size_t k = 0; k < n; ++k)
      if (!(bits[k / 64] >> (k % 64) & 1)) missing.push_back(lo + k);
  }
  return missing;
}

}  // namespace

std::vector<StepRecord> reduce_history(const LammpsSession& lmp, const std::vector<LocalRecord>& local,
                                       uint64_t first) {
  const size_t n = local.size();
  std::vector<double> sums(4 * n), maxes(2 * n);
  for (size_t s = 0; s < n; ++s) {
    const LocalRecord& r = local[s];
    sums[4 * s] = r.kinetic_energy, sums[4 * s + 1] = r.colliding_pairs, sums[4 * s + 2] = r.flagged,
             sums[4 * s + 3] = r.particles;
    maxes[2 * s] = r.max_speed, maxes[2 * s + 1] = r.max_displacement;
  }
  if (lmp.ranks() > 1 && n > 0) {
    MPI_Allreduce(MPI_IN_PLACE, sums.data(), static_cast<int>(sums.size()), MPI_DOUBLE, MPI_SUM, lmp.comm());
    MPI_Allreduce(MPI_IN_PLACE, maxes.data(), static_cast<int>(maxes.size()), MPI_DOUBLE, MPI_MAX, lmp.comm());
  }
  std::vector<StepRecord> out(n);
  for (size_t s = 0; s < n; ++s) {
    StepRecord& r = out[s];
    r.step = first + s;
    r.kinetic_energy = sums[4 * s];
    r.colliding_pairs = static_cast<uint32_t>(sums[4 * s + 1]);
    r.flagged = static_cast<uint32_t>(sums[4 * s + 2]);
    r.particles = static_cast<uint32_t>(sums[4 * s + 3]);
    r.max_speed = maxes[2 * s];
    r.max_displacement = maxes[2 * s + 1];
    r.power = local[s].power;  // FIRE's P, over every rank already
  }
  return out;
}

std::vector<Particle> gather_particles(const LammpsSession& lmp, size_t count, const EngineParams& params,
                                       const Vec3& centre) {
  // Each rank's own atoms: index, x, v, radius, id (9 doubles each), gathered on every rank.
  const AtomIndices own(lmp);
  double** x = lmp.atoms<double**>("x");
  double** v = lmp.atoms<double**>("v");
  double* radius = lmp.atoms<double*>("radius");
  std::vector<double> mine(9 * static_cast<size_t>(own.count));
  for (int i = 0; i < own.count; ++i) {
    double* m = &mine[9 * static_cast<size_t>(i)];
    m[0] = own.index[i], m[1] = x[i][0], m[2] = x[i][1], m[3] = x[i][2];
    m[4] = v[i][0], m[5] = v[i][1], m[6] = v[i][2], m[7] = radius[i], m[8] = own.id[i];
  }
  const std::vector<double> all = lmp.gather(mine);
  std::vector<Particle> out(count);
  std::vector<bool> seen(count, false);
  for (size_t k = 0; k + 8 < all.size(); k += 9) {
    const size_t index = static_cast<size_t>(all[k]);
    if (index >= count) continue;
    Particle& p = out[index];
    p.position = {all[k + 1], all[k + 2], all[k + 3]};
    p.velocity = {all[k + 4], all[k + 5], all[k + 6]};
    p.radius = all[k + 7];
    p.mass = particle_mass(params, p.radius);
    p.id = static_cast<uint64_t>(all[k + 8]);
    seen[index] = true;
  }
  for (size_t i = 0; i < out.size(); ++i) {
    if (!seen[i]) {  // lost by LAMMPS (left its box): flagged, to be removed
      out[i].position = centre;
      out[i].radius = params.radius;
      out[i].mass = 1;
    }
  }
  return out;
}

std::vector<size_t> gather_flagged(const LammpsSession& lmp, size_t count, const std::unordered_set<int>& flagged) {
  // The flagged tags to every rank (an atom may have moved on since its
  // rank flagged it); each names the indices of those it holds now.
  const std::vector<double> tags = lmp.gather(std::vector<double>(flagged.begin(), flagged.end()));
  std::vector<size_t> out;
  if (!tags.empty()) {
    std::unordered_set<int> wanted;
    for (double t : tags) wanted.insert(static_cast<int>(t));
    const AtomIndices own(lmp);
    const int* tag = lmp.atoms<int*>("id");
    std::vector<uint64_t> mine;
    for (int i = 0; i < own.count; ++i)
      if (wanted.count(tag[i])) mine.push_back(static_cast<uint64_t>(own.index[i]));
    for (uint64_t index : lmp.gather(mine)) out.push_back(static_cast<size_t>(index));
  }
  if (static_cast<double>(count) != lmp.natoms())
    for (size_t index : missing_indices(lmp, count)) out.push_back(index);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace lammps_engine
}  // namespace pfill
#endif
