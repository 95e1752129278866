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
  std::vector<bool> moving(particles.size(), false);
  for (uint32_t i : region.moving) moving[i] = true;
  std::vector<Particle> back;
  back.reserve(region.moving.size());
  for (const Particle& q : moved) {
    if (q.id >= particles.size() || !moving[q.id]) continue;  // held: did not move
    back.push_back(particles[q.id]);
    back.back().position = q.position;
  }
  // the others in their order (compacted in place: a copy would cost 70 MiB at 1e6), then the moved
  size_t kept = 0;
  for (size_t i = 0; i < particles.size(); ++i)
    if (!moving[i]) particles[kept++] = particles[i];
  particles.resize(kept);
  particles.insert(particles.end(), back.begin(), back.end());
  for (Particle& p : particles) p.velocity = {};
  return particles;
}

}  // namespace pfill
