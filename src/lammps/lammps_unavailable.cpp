// A pfill built without LAMMPS (PFILL_WITH_LAMMPS OFF, or LAMMPS/MPI not
// found): the LAMMPS engine's entry points say so in one line.
#ifndef PFILL_WITH_LAMMPS
#include "pfill/error.hpp"
#include "pfill/lammps.hpp"

namespace pfill {
namespace {
const char* kNoLammps =
    "this pfill was built without LAMMPS; install liblammps-dev libopenmpi-dev openmpi-bin and rebuild "
    "(cmake -DPFILL_WITH_LAMMPS=ON), or leave out --engine lammps";
}

bool lammps_available() { return false; }
MpiWorld lammps_mpi_start() { return {}; }
void lammps_mpi_abort(int) {}
std::shared_ptr<ProcessGroup> lammps_process_group() { return std::make_shared<ProcessGroup>(); }
std::unique_ptr<ParticleEngine> make_lammps_engine(const EngineParams&) { throw Error(kNoLammps); }
std::function<std::unique_ptr<ParticleEngine>(const EngineParams&)> lammps_engine_factory() { throw Error(kNoLammps); }

}  // namespace pfill
#endif
