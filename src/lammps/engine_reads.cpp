// The LAMMPS engine's reads: see engine_reads.hpp.
#ifdef PFILL_WITH_LAMMPS
#include "lammps/engine_reads.hpp"

#include <algorithm>
#include <unordered_map>

namespace pfill {
namespace lammps_engine {
namespace {

/// Atoms LAMMPS dropped (past its box): the book's tags it no longer has.
void find_lost(const LammpsSession& lmp, ParticleBook& book) {
  const int nl = lmp.nlocal();
  int* tag = lmp.atoms<int*>("id");
  std::vector<double> mine(tag, tag + nl);
  std::vector<double> all = lmp.gather(mine);
  std::unordered_map<int, bool> present;
  for (double t : all) present[static_cast<int>(t)] = true;
  for (int t : book.tags())
    if (!present.count(t)) book.lost().insert(t);
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

std::vector<Particle> gather_particles(const LammpsSession& lmp, ParticleBook& book, const EngineParams& params,
                                       const Vec3& centre) {
  // Each rank's own atoms: tag, x, v, radius (8 doubles each), gathered on every rank.
  const int nl = lmp.nlocal();
  int* tag = lmp.atoms<int*>("id");
  double** x = lmp.atoms<double**>("x");
  double** v = lmp.atoms<double**>("v");
  double* radius = lmp.atoms<double*>("radius");
  std::vector<double> mine(8 * static_cast<size_t>(nl));
  for (int i = 0; i < nl; ++i) {
    double* m = &mine[8 * static_cast<size_t>(i)];
    m[0] = tag[i], m[1] = x[i][0], m[2] = x[i][1], m[3] = x[i][2];
    m[4] = v[i][0], m[5] = v[i][1], m[6] = v[i][2], m[7] = radius[i];
  }
  std::vector<double> all = lmp.gather(mine);
  std::vector<Particle> out(book.size());
  std::vector<bool> seen(book.size(), false);
  for (size_t k = 0; k + 7 < all.size(); k += 8) {
    const size_t index = book.index_of(static_cast<int>(all[k]));
    if (index == book.size()) continue;
    Particle& p = out[index];
    p.position = {all[k + 1], all[k + 2], all[k + 3]};
    p.velocity = {all[k + 4], all[k + 5], all[k + 6]};
    p.radius = all[k + 7];
    p.mass = particle_mass(params, p.radius);
    seen[index] = true;
  }
  for (size_t i = 0; i < out.size(); ++i) {
    out[i].id = book.id(i);
    if (!seen[i]) {  // lost by LAMMPS (left its box): flagged, to be removed
      book.lost().insert(book.tag(i));
      out[i].position = centre;
      out[i].radius = params.radius;
      out[i].mass = 1;
    }
  }
  return out;
}

std::vector<size_t> gather_flagged(const LammpsSession& lmp, ParticleBook& book,
                                   const std::unordered_set<int>& flagged) {
  if (static_cast<double>(book.size()) != lmp.natoms()) find_lost(lmp, book);
  std::vector<double> mine(flagged.begin(), flagged.end());
  std::vector<double> all = lmp.gather(mine);
  for (int t : book.lost()) all.push_back(t);  // the same on every rank
  std::vector<size_t> out;
  for (double t : all) {
    const size_t index = book.index_of(static_cast<int>(t));
    if (index != book.size()) out.push_back(index);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace lammps_engine
}  // namespace pfill
#endif
