// The engine's particles as a ParticleSet (what metrics, files and callers
// take): positions, radii, velocities and ids.
#pragma once
#include <vector>

#include "pfill/engine/engine.hpp"
#include "pfill/particles.hpp"

namespace pfill {

inline ParticleSet to_particle_set(const std::vector<Particle>& ps) {
  ParticleSet set;
  set.positions.reserve(ps.size());
  set.radii.reserve(ps.size());
  set.velocities.reserve(ps.size());
  set.ids.reserve(ps.size());
  for (const Particle& p : ps) {
    set.positions.push_back(p.position);
    set.radii.push_back(p.radius);
    set.velocities.push_back(p.velocity);  // written with --velocities
    set.ids.push_back(p.id);
  }
  return set;
}

}  // namespace pfill
