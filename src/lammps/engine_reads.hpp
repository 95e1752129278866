// The LAMMPS engine's reads (docs/lammps_engine.md "SPMD across ranks"):
// each rank holds only its own atoms and its own step records, so every
// read is a collective over the ranks, with the same result on every
// rank: the records reduced (sums and maxima), the particles, the flagged
// and the lost gathered, in the engine's indices (atom_indices.hpp).
#pragma once
#ifdef PFILL_WITH_LAMMPS
#include <cstdint>
#include <unordered_set>
#include <vector>

#include "lammps/lammps_session.hpp"
#include "lammps/step_callback.hpp"
#include "pfill/engine/particle_engine.hpp"

namespace pfill {
namespace lammps_engine {

/// The ranks' records of the same steps reduced into StepRecords, the
/// first numbered `first` (collective).
std::vector<StepRecord> reduce_history(const LammpsSession& lmp, const std::vector<LocalRecord>& local,
                                       uint64_t first);

/// Every particle (`count` of them), in the engine's order, on every rank
/// (collective); those LAMMPS lost (past its box) are given at `centre`
/// with the engine's radius and id 0: flagged_particles names them.
std::vector<Particle> gather_particles(const LammpsSession& lmp, size_t count, const EngineParams& params,
                                       const Vec3& centre);

/// The indices of the flagged (`flagged`: this rank's tags) and, where
/// LAMMPS holds fewer atoms than the engine's `count`, of the lost (those
/// no rank holds), ascending, on every rank (collective).
std::vector<size_t> gather_flagged(const LammpsSession& lmp, size_t count, const std::unordered_set<int>& flagged);

}  // namespace lammps_engine
}  // namespace pfill
#endif
