// The LAMMPS engine's indices and tags: see particle_book.hpp.
#include "lammps/particle_book.hpp"

#include <algorithm>
#include <functional>
#include <limits>
#include <map>
#include <string>

#include "pfill/error.hpp"

namespace pfill {
namespace lammps_engine {

int ParticleBook::new_tags(size_t n) {
  // LAMMPS' atom ids are 32-bit in this build (tagint int): past 2^31 - 1
  // ids it would stop the program; the fill births more than it keeps.
  const int64_t first = next_tag_, last = next_tag_ + static_cast<int64_t>(n) - 1;
  if (last > std::numeric_limits<int>::max())
    throw Error("lammps engine: more than 2,147,483,647 particles born over the fill, past LAMMPS' 32-bit atom ids");
  next_tag_ += static_cast<int64_t>(n);
  return static_cast<int>(first);
}

Removal ParticleBook::remove(std::vector<size_t> indices) {
  std::sort(indices.begin(), indices.end(), std::greater<size_t>());
  indices.erase(std::unique(indices.begin(), indices.end()), indices.end());
  if (!indices.empty() && indices.front() >= size_)
    throw Error("lammps engine: cannot remove particle " + std::to_string(indices.front()) + " of " +
                std::to_string(size_));
  // The swaps on indices alone: who sits where the last ones went (a place
  // not in the map holds its own particle).
  std::map<size_t, size_t> holder;
  auto at = [&holder](size_t place) {
    const auto it = holder.find(place);
    return it == holder.end() ? place : it->second;
  };
  for (size_t idx : indices) {
    const size_t last = size_ - 1, moving = at(last);
    holder.erase(last);
    if (idx != last) holder[idx] = moving;
    --size_;
  }
  Removal r;
  r.gone.assign(indices.rbegin(), indices.rend());
  for (const auto& [place, original] : holder)
    if (place != original) r.moves.push_back({original, place});
  return r;
}

}  // namespace lammps_engine
}  // namespace pfill
