// Finding holes in a packing that can take another sphere.
#include "pfill/voids.hpp"

#include "fill/centre_grid.hpp"

namespace pfill {

std::vector<Vec3> find_voids(const ParticleSet& particles, const ScalarGrid& sdf, double radius, double clearance,
                             size_t limit) {
  std::vector<Vec3> voids;
  CentreGrid grid(particles.positions, clearance);
  const double c2 = clearance * clearance;
  uint32_t next_id = static_cast<uint32_t>(particles.size());
  auto taken = [&](const Vec3& p) {
    bool near = false;
    grid.for_near(p, [&](uint32_t id) {
      if (near) return;
      const Vec3 q = id < particles.size() ? particles.positions[id] : voids[id - particles.size()];
      const Vec3 d = q - p;
      near = dot(d, d) < c2;
    });
    return near;
  };
  for (int k = 0; k < sdf.dims[2] && voids.size() < limit; ++k)
    for (int j = 0; j < sdf.dims[1] && voids.size() < limit; ++j)
      for (int i = 0; i < sdf.dims[0] && voids.size() < limit; ++i) {
        if (-sdf.at(i, j, k) < radius) continue;
        const Vec3 p = sdf.point(i, j, k);
        if (taken(p)) continue;
        voids.push_back(p);
        grid.insert(p, next_id++);
      }
  return voids;
}

}  // namespace pfill
