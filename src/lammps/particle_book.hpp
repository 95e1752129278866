// The LAMMPS engine's indices (docs/lammps_engine.md "Indices, ids, births
// and removals"): what read_particles, flagged_particles and
// remove_particles speak of, the same on every rank. An index maps to a
// LAMMPS tag and to the caller's Particle::id; a map gives the index of a
// tag. Births take consecutive new tags at the end; removals swap with the
// last, as the other engines do. No LAMMPS or MPI here.
#pragma once

#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace pfill {
namespace lammps_engine {

class ParticleBook {
 public:
  /// n new tags, consecutive, never given before; throws pfill::Error past
  /// LAMMPS' largest id (2^31 - 1).
  std::vector<int> new_tags(size_t n);
  /// The next index: the particle with this tag and caller's id.
  void append(int tag, uint64_t id);
  /// Removes the particles at these indices (each once; the last fills each
  /// hole, from the largest index down) and returns their tags, ascending.
  /// Throws pfill::Error for an index past the end, before changing anything
  /// at or below it.
  std::vector<int> remove(std::vector<size_t> indices);

  size_t size() const { return order_.size(); }
  int tag(size_t index) const { return order_[index]; }
  uint64_t id(size_t index) const { return ids_[index]; }
  const std::vector<int>& tags() const { return order_; }
  /// The index of a tag, or size() where the tag is not the engine's.
  size_t index_of(int tag) const;

  /// Tags LAMMPS dropped (atoms past its box): the same on every rank.
  std::unordered_set<int>& lost() { return lost_; }

 private:
  std::vector<int> order_;                // index -> LAMMPS tag
  std::vector<uint64_t> ids_;             // index -> the caller's id
  std::unordered_map<int, size_t> index_of_;
  int64_t next_tag_ = 1;
  std::unordered_set<int> lost_;
};

}  // namespace lammps_engine
}  // namespace pfill
