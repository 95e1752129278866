// The LAMMPS engine's MPI entry points (pfill/lammps.hpp): whether LAMMPS
// is built in, MPI started once for the program's ranks, and an abort that
// ends every rank where more than one runs.
#ifdef PFILL_WITH_LAMMPS
#include "lammps/lammps_session.hpp"
#include "pfill/lammps.hpp"

namespace pfill {

bool lammps_available() { return true; }

MpiWorld lammps_mpi_start() {
  lammps_engine::ensure_mpi();
  MpiWorld w;
  MPI_Comm_rank(MPI_COMM_WORLD, &w.rank);
  MPI_Comm_size(MPI_COMM_WORLD, &w.size);
  return w;
}

void lammps_mpi_abort(int code) {
  int initialized = 0, finalized = 0;
  MPI_Initialized(&initialized);
  MPI_Finalized(&finalized);
  if (!initialized || finalized) return;
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (size > 1) MPI_Abort(MPI_COMM_WORLD, code);
}

}  // namespace pfill
#endif
