// The LAMMPS engine's indices, tags and ids: see particle_book.hpp.
#include "lammps/particle_book.hpp"

#include <algorithm>
#include <functional>
#include <limits>
#include <string>

#include "pfill/error.hpp"

namespace pfill {
namespace lammps_engine {

std::vector<int> ParticleBook::new_tags(size_t n) {
  // LAMMPS' atom ids are 32-bit in this build (tagint int): past 2^31 - 1
  // ids it would stop the program; the fill births more than it keeps.
  const int64_t last = next_tag_ + static_cast<int64_t>(n) - 1;
  if (last > std::numeric_limits<int>::max())
    throw Error("lammps engine: more than 2,147,483,647 particles born over the fill, past LAMMPS' 32-bit atom ids");
  std::vector<int> tags(n);
  for (int& t : tags) t = static_cast<int>(next_tag_++);
  return tags;
}

void ParticleBook::append(int tag, uint64_t id) {
  index_of_[tag] = order_.size();
  order_.push_back(tag);
  ids_.push_back(id);
}

std::vector<int> ParticleBook::remove(std::vector<size_t> indices) {
  std::sort(indices.begin(), indices.end(), std::greater<size_t>());
  indices.erase(std::unique(indices.begin(), indices.end()), indices.end());
  std::vector<int> gone;
  for (size_t idx : indices) {
    if (idx >= order_.size()) throw Error("lammps engine: cannot remove particle " + std::to_string(idx));
    const int tag = order_[idx];
    gone.push_back(tag);
    index_of_.erase(tag);
    order_[idx] = order_.back();
    ids_[idx] = ids_.back();
    order_.pop_back();
    ids_.pop_back();
    if (idx < order_.size()) index_of_[order_[idx]] = idx;
  }
  std::sort(gone.begin(), gone.end());
  return gone;
}

size_t ParticleBook::index_of(int tag) const {
  auto it = index_of_.find(tag);
  return it == index_of_.end() ? order_.size() : it->second;
}

}  // namespace lammps_engine
}  // namespace pfill
