// Each LAMMPS atom's engine index and caller's id, carried by the atom
// itself (`fix property/atom`: LAMMPS moves them with it between ranks and
// through its sorts), so that no rank keeps a book of every particle
// (issue 31). The index is the one ParticleEngine speaks of
// (particle_book.hpp says how removals move it); the id is
// Particle::id, as a double (exact below 2^53).
#pragma once
#ifdef PFILL_WITH_LAMMPS
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "lammps/lammps_session.hpp"

namespace pfill {
namespace lammps_engine {

/// The largest caller's id an atom carries exactly (2^53: a double's integers).
constexpr uint64_t kLargestAtomId = uint64_t{1} << 53;

/// The command that gives every atom the two properties (before any atom exists).
const char* atom_index_fix();

/// This rank's own atoms' indices and ids (re-read after atoms are created or deleted).
struct AtomIndices {
  int* index = nullptr;
  double* id = nullptr;
  int count = 0;  ///< nlocal

  explicit AtomIndices(const LammpsSession& s);
  uint64_t id_of(int i) const { return static_cast<uint64_t>(id[i]); }
};

/// (index, local i) of this rank's own atoms, ascending by index.
std::vector<std::pair<size_t, int>> own_by_index(const LammpsSession& s);

}  // namespace lammps_engine
}  // namespace pfill
#endif
