// The LAMMPS engine's indices (docs/lammps_engine.md "Indices, ids, births
// and removals"): what read_particles, flagged_particles and
// remove_particles speak of, the same on every rank. The book holds no
// particle (issue 31: no rank holds anything of every particle): each
// atom carries its own index and the caller's id as per-atom properties
// (atom_indices.hpp); the book keeps only the count and the next tag, and
// works out what a removal does to the indices. Births take consecutive
// new tags at the end; removals swap with the last, as the other engines
// do. No LAMMPS or MPI here.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace pfill {
namespace lammps_engine {

/// What removing a set of indices does: which go (ascending), and where
/// each survivor the last ones filled holes with moves (old index, new
/// index; survivors not named keep theirs).
struct Removal {
  std::vector<size_t> gone;
  std::vector<std::pair<size_t, size_t>> moves;
};

class ParticleBook {
 public:
  /// n new tags, consecutive, never given before (the first returned);
  /// throws pfill::Error past LAMMPS' largest id (2^31 - 1).
  int new_tags(size_t n);
  /// n particles appended at the next indices.
  void added(size_t n) { size_ += n; }
  /// Removes the particles at these indices (repeats ignored; the last
  /// fills each hole, from the largest index down): the book's count falls,
  /// and the result says who went and who moved. Throws pfill::Error for an
  /// index past the end, before changing anything.
  Removal remove(std::vector<size_t> indices);

  size_t size() const { return size_; }

 private:
  size_t size_ = 0;
  int64_t next_tag_ = 1;
};

}  // namespace lammps_engine
}  // namespace pfill
