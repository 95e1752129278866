// What a rank sees of the other ranks' atoms at P > 1 (issue 31,
// docs/lammps_engine.md "SPMD across ranks"): its own atoms and every other
// rank's atoms within a reach of its sub-domain, exchanged when asked
// (MPI_Alltoallv). The births' room test (birth_halo) and the finish's
// rounds (local_halo) decide with them, so no rank gathers all positions.
// Not LAMMPS' own ghosts: after a run they hold the positions from before
// the last step's drift (the callback drifts after the forward
// communication), lammps_create_atoms and delete_atoms drop them, and a
// ghost cutoff as large as these reaches (one rest distance for the room
// sites, two contact distances for the finish) would widen every step's
// communication.
#pragma once
#ifdef PFILL_WITH_LAMMPS
#include "lammps/lammps_session.hpp"
#include "pfill/engine/birth_view.hpp"
#include "pfill/engine/local_view.hpp"

namespace pfill {
namespace lammps_engine {

/// This rank's atoms (owned: nlocal) and the atoms of other ranks whose
/// centre lies within `reach` of this rank's sub-domain; the regions are
/// every rank's sub-domain. Collective.
BirthView birth_halo(const LammpsSession& s, double reach);

/// The same for the finish: this rank's atoms whole, in the order of the
/// engine's indices (atom_indices.hpp), then the halo's (positions, radii, ids);
/// keys are LAMMPS tags. Collective.
LocalView local_halo(const LammpsSession& s, const EngineParams& params, double reach);

}  // namespace lammps_engine
}  // namespace pfill
#endif
