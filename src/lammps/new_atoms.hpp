// A batch of births as one rank hands it to LAMMPS (docs/lammps_engine.md
// "Indices, ids, births and removals"): each atom's tag, position,
// velocity, radius, mass and caller's id; atoms decided on a sub-domain that has since
// moved sent on to every rank; the atoms created, and the radius and mass
// set of those this rank keeps (lammps_create_atoms gives 0.5 and density 1).
#pragma once
#ifdef PFILL_WITH_LAMMPS
#include <cstdint>
#include <vector>

#include "lammps/lammps_session.hpp"
#include "pfill/engine/particle_engine.hpp"

namespace pfill {
namespace lammps_engine {

struct NewAtoms {
  std::vector<int> tags;          ///< ascending (lammps_create_atoms keeps this order per rank)
  std::vector<double> x, v;       ///< 3 each
  std::vector<double> radius, mass;
  std::vector<uint64_t> ids;      ///< Particle::id

  size_t size() const { return tags.size(); }
  void add(int tag, const Particle& p, double m);
  /// Orders the atoms by tag (a no-op where they are in order already).
  void sort_by_tag();
};

/// How many of `atoms` lie outside this rank's sub-domain now, as
/// lammps_create_atoms tests it (half-open [sublo, subhi)).
size_t outside_subdomain(const LammpsSession& s, const NewAtoms& atoms);

/// Each rank's atoms outside its sub-domain now (decided on an older one)
/// go to every rank and are appended there: lammps_create_atoms keeps each
/// on the one rank whose sub-domain holds it. Returns how many this rank
/// sent. Collective (one MPI_Allreduce; an MPI_Allgatherv where any).
size_t share_strays(const LammpsSession& s, NewAtoms& atoms);

/// Creates the atoms (collective) and sets radius, mass, index and id of
/// those this rank keeps (atom_indices.hpp): the batch's tags run from
/// first_tag, its indices from first_index in the same order. Returns how
/// many were created over all ranks.
int create_new_atoms(LammpsSession& s, const NewAtoms& atoms, int first_tag, size_t first_index);

}  // namespace lammps_engine
}  // namespace pfill
#endif
