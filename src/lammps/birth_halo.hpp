// The births' room test on the LAMMPS engine at P > 1 ranks (issue 31,
// docs/lammps_engine.md "SPMD across ranks"): each rank sees its own atoms
// and every other rank's atoms within the test's reach of its sub-domain,
// exchanged once a wave (MPI_Alltoallv), and decides the sites inside its
// sub-domain. No rank gathers all positions. Not LAMMPS' own ghosts: after
// a run they hold the positions from before the last step's drift (the
// callback drifts after the forward communication), lammps_create_atoms and
// delete_atoms drop them, and a ghost cutoff as large as the room sites'
// clearance (one rest distance) would widen every step's communication.
#pragma once
#ifdef PFILL_WITH_LAMMPS
#include "lammps/lammps_session.hpp"
#include "pfill/engine/birth_view.hpp"

namespace pfill {
namespace lammps_engine {

/// This rank's atoms (owned: nlocal) and the atoms of other ranks whose
/// centre lies within `reach` of this rank's sub-domain; the regions are
/// every rank's sub-domain. Collective.
BirthView birth_halo(const LammpsSession& s, double reach);

}  // namespace lammps_engine
}  // namespace pfill
#endif
