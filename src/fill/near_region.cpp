// The spheres around a few places (near_region.hpp).
#include "fill/near_region.hpp"

#include "fill/centre_grid.hpp"

namespace pfill {

NearRegion region_near(const std::vector<Particle>& particles, const std::vector<Vec3>& places, double reach,
                       double hold) {
  NearRegion region;
  if (places.empty()) return region;
  const double outer = reach + hold;
  const CentreGrid grid(places, outer);  // a cell of `outer`: every place within it lies in the 27 around
  for (size_t i = 0; i < particles.size(); ++i) {
    const Vec3& p = particles[i].position;
    double nearest2 = outer * outer;
    grid.for_near(p, [&](uint32_t k) {
      const Vec3 d = places[k] - p;
      nearest2 = std::min(nearest2, dot(d, d));
    });
    if (nearest2 < reach * reach)
      region.moving.push_back(static_cast<uint32_t>(i));
    else if (nearest2 < outer * outer)
      region.held.push_back(static_cast<uint32_t>(i));
  }
  return region;
}

std::vector<Particle> region_particles(const std::vector<Particle>& particles, const NearRegion& region,
                                       double held_mass) {
  std::vector<Particle> part;
  part.reserve(region.moving.size() + region.held.size());
  for (uint32_t i : region.moving) part.push_back(particles[i]);
  for (uint32_t i : region.held) {
    part.push_back(particles[i]);
    part.back().mass = held_mass;
  }
  for (size_t k = 0; k < part.size(); ++k) {
    part[k].id = k < region.moving.size() ? region.moving[k] : region.held[k - region.moving.size()];
    part[k].velocity = {};  // a relaxation starts at rest
  }
  return part;
}

std::vector<Particle> with_moved(std::vector<Particle> particles, const NearRegion& region,
                                 const std::vector<Particle>& moved) {
  std::vector<uint8_t> state(particles.size(), 0);  // 1: moving, not (yet) found in `moved`; 2: held
  for (uint32_t i : region.moving) state[i] = 1;
  for (uint32_t i : region.held) state[i] = 2;
  for (const Particle& q : moved) {
    if (q.id >= particles.size() || state[q.id] != 1) continue;  // held: did not move
    particles[q.id].position = q.position;
    state[q.id] = 0;
  }
  // compacted in place: at 1e6 spheres a copy would cost another 70 MiB
  size_t kept = 0;
  for (size_t i = 0; i < particles.size(); ++i)
    if (state[i] != 1) {
      particles[kept] = particles[i];
      particles[kept++].velocity = {};
    }
  particles.resize(kept);
  return particles;
}

}  // namespace pfill
