// The default of ParticleEngine::add_decided_particles (particle_engine.hpp):
// one process decides the whole batch, which goes on in its places' order.
#include <string>
#include <vector>

#include "pfill/engine/particle_engine.hpp"
#include "pfill/error.hpp"

namespace pfill {

size_t ParticleEngine::add_decided_particles(const std::vector<Particle>& mine, const std::vector<size_t>& places,
                                             size_t count) {
  if (mine.size() != count || places.size() != count)
    throw Error("engine: " + std::to_string(count) + " particles in the batch, " + std::to_string(mine.size()) +
                " given; one process must give them all");
  std::vector<Particle> batch(count);
  std::vector<bool> taken(count, false);
  for (size_t k = 0; k < count; ++k) {
    if (places[k] >= count || taken[places[k]])
      throw Error("engine: the batch's places must name each of 0.." + std::to_string(count - 1) + " once");
    taken[places[k]] = true;
    batch[places[k]] = mine[k];
  }
  return add_particles(batch);
}

}  // namespace pfill
