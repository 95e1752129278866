// What the LAMMPS engine's births split over ranks handed to LAMMPS in this
// process (issue 31, ParticleEngine::add_decided_particles): counts for the
// tests, which check that each rank creates only its own sub-domain's
// newborns. No LAMMPS or MPI here, so the tests read it in any build.
#pragma once

#include <cstdint>

namespace pfill {
namespace lammps_engine {

struct BirthTally {
  uint64_t batches = 0;   ///< add_decided_particles calls with births
  uint64_t newborns = 0;  ///< the batches' members, over all ranks
  uint64_t passed = 0;    ///< atoms this rank passed to lammps_create_atoms (its own and strays)
  uint64_t outside = 0;   ///< of its own, those outside its sub-domain then (strays it sent to all)
};

/// This process's tally, over every engine it made; tests reset it.
BirthTally& birth_tally();

}  // namespace lammps_engine
}  // namespace pfill
