// The output's parts per rank (`-o out.%r.csv` with --engine lammps,
// docs/lammps_engine.md "Output per rank"): each rank writes the particles
// in its LAMMPS sub-domain, so that the parts tile the fill and
// `pfill join` gives back the whole.
#ifdef PFILL_WITH_LAMMPS
#include <algorithm>
#include <cmath>
#include <vector>

#include "lammps/lammps_session.hpp"
#include "pfill/engine/birth_view.hpp"
#include "pfill/lammps.hpp"

namespace pfill {

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
  std::vector<double> all(6 * static_cast<size_t>(ranks));
  MPI_Allgather(box, 6, MPI_DOUBLE, all.data(), 6, MPI_DOUBLE, MPI_COMM_WORLD);
  // The rule the births' sites follow too (owning_region: half-open boxes, else the nearest).
  std::vector<Box3> boxes(static_cast<size_t>(ranks));
  for (size_t r = 0; r < boxes.size(); ++r)
    boxes[r].lo = {all[6 * r], all[6 * r + 1], all[6 * r + 2]}, boxes[r].hi = {all[6 * r + 3], all[6 * r + 4], all[6 * r + 5]};
  for (size_t i = 0; i < positions.size(); ++i)
    if (owning_region(boxes, positions[i]) == rank) mine.push_back(i);
  return mine;
}

}  // namespace pfill
#endif
