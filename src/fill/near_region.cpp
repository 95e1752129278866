// The spheres around a few places (near_region.hpp).
#include "fill/near_region.hpp"

#include <algorithm>

namespace pfill {

NearParts::NearParts(const std::vector<Vec3>& places, double reach, double hold)
    : places_(places), reach2_(reach * reach), outer2_((reach + hold) * (reach + hold)), grid_(places, reach + hold) {}

ParticleEngine::StepPart NearParts::operator()(const Vec3& p) const {
  double nearest2 = outer2_;
  grid_.for_near(p, [&](uint32_t k) {
    const Vec3 d = places_[k] - p;
    nearest2 = std::min(nearest2, dot(d, d));
  });
  if (nearest2 < reach2_) return ParticleEngine::StepPart::moving;
  return nearest2 < outer2_ ? ParticleEngine::StepPart::held : ParticleEngine::StepPart::out;
}

NearRegion region_near(const std::vector<Particle>& particles, const std::vector<Vec3>& places, double reach,
                       double hold) {
  NearRegion region;
  if (places.empty()) return region;
  const NearParts part_of(places, reach, hold);
  for (size_t i = 0; i < particles.size(); ++i) {
    const ParticleEngine::StepPart part = part_of(particles[i].position);
    if (part == ParticleEngine::StepPart::moving)
      region.moving.push_back(static_cast<uint32_t>(i));
    else if (part == ParticleEngine::StepPart::held)
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
