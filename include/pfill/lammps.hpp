/// @file lammps.hpp
/// @brief The LAMMPS engine (`pfill fill --engine lammps`): the fill's
/// particles on LAMMPS, across MPI ranks (docs/lammps_engine.md). No LAMMPS
/// or MPI header is seen from here; a pfill built without LAMMPS
/// (PFILL_WITH_LAMMPS off, or not found) answers lammps_available() false
/// and throws pfill::Error from the rest.
#pragma once
#include <functional>
#include <memory>
#include <vector>

#include "pfill/engine/particle_engine.hpp"

namespace pfill {

/// Whether this pfill was built with the LAMMPS engine.
bool lammps_available();

/// The MPI world the LAMMPS engine runs on.
struct MpiWorld {
  int rank = 0;  ///< this process's rank
  int size = 1;  ///< the number of ranks (mpirun -np P)
};

/// Starts MPI once per process (MPI_Init; MPI_Finalize at exit) and says
/// where this process stands. Without LAMMPS: rank 0 of 1, nothing started.
MpiWorld lammps_mpi_start();

/// Ends every rank at once (MPI_Abort) with `code`: for an error one rank
/// met alone, which would leave the others waiting. Returns when MPI is not
/// running (one process, or no LAMMPS).
void lammps_mpi_abort(int code);

/// A LammpsEngine on MPI_COMM_WORLD (MPI started if it was not). Every
/// rank must make the same calls with the same arguments (SPMD): births,
/// removals and reads are collective.
std::unique_ptr<ParticleEngine> make_lammps_engine(const EngineParams& params);

/// The MPI ranks as a ProcessGroup (MPI_COMM_WORLD), for the command
/// line's output after a fill: a gather to rank 0, or nothing when every
/// rank writes its own part. One process, MPI not started, or no LAMMPS:
/// the group of one.
std::shared_ptr<ProcessGroup> lammps_process_group();

/// FillOptions::engine for the LAMMPS engine; throws pfill::Error ("this
/// pfill was built without LAMMPS; ...") when it is not built in.
std::function<std::unique_ptr<ParticleEngine>(const EngineParams&)> lammps_engine_factory();

}  // namespace pfill
