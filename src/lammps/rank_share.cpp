// The output's parts per rank (`-o out.%r.csv` with --engine lammps,
// docs/lammps_engine.md "Output per rank"): each rank writes the particles
// in its LAMMPS sub-domain, so that the parts tile the fill and
// `pfill join` gives back the whole.
#ifdef PFILL_WITH_LAMMPS
#include <algorithm>
#include <cmath>
#include <vector>

#include "lammps/lammps_session.hpp"
#include "pfill/lammps.hpp"

namespace pfill {
namespace {

/// How far p lies outside box b (0 inside or on it).
double distance_to(const double* b, const Vec3& p) {
  const double c[3] = {p.x, p.y, p.z};
  double d2 = 0;
  for (int a = 0; a < 3; ++a) {
    const double out = std::max({b[a] - c[a], c[a] - b[3 + a], 0.0});
    d2 += out * out;
  }
  return std::sqrt(d2);
}

/// The first rank whose half-open box [lo, hi) holds p; else the nearest box.
int owner(const std::vector<double>& boxes, int ranks, const Vec3& p) {
  const double c[3] = {p.x, p.y, p.z};
  for (int r = 0; r < ranks; ++r) {
    const double* b = &boxes[6 * static_cast<size_t>(r)];
    if (c[0] >= b[0] && c[1] >= b[1] && c[2] >= b[2] && c[0] < b[3] && c[1] < b[4] && c[2] < b[5]) return r;
  }
  int best = 0;
  for (int r = 1; r < ranks; ++r)
    if (distance_to(&boxes[6 * static_cast<size_t>(r)], p) < distance_to(&boxes[6 * static_cast<size_t>(best)], p))
      best = r;
  return best;
}

}  // namespace

std::vector<size_t> lammps_rank_share(const std::vector<Vec3>& positions) {
  std::vector<size_t> mine;
  int initialized = 0, ranks = 1, rank = 0;
  MPI_Initialized(&initialized);
  if (initialized) MPI_Comm_size(MPI_COMM_WORLD, &ranks), MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  const lammps_engine::SubDomain& d = lammps_engine::last_subdomain();
  // The same answer on every rank: all or none of them have run an engine (SPMD).
  if (ranks == 1 || !d.set) {
    if (rank == 0)
      for (size_t i = 0; i < positions.size(); ++i) mine.push_back(i);
    return mine;
  }
  const double box[6] = {d.lo[0], d.lo[1], d.lo[2], d.hi[0], d.hi[1], d.hi[2]};
  std::vector<double> boxes(6 * static_cast<size_t>(ranks));
  MPI_Allgather(box, 6, MPI_DOUBLE, boxes.data(), 6, MPI_DOUBLE, MPI_COMM_WORLD);
  for (size_t i = 0; i < positions.size(); ++i)
    if (owner(boxes, ranks, positions[i]) == rank) mine.push_back(i);
  return mine;
}

}  // namespace pfill
#endif
