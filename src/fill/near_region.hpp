// The spheres around a few places in a packing: those that may move (within
// `reach` of one) and those held still around them (within `reach + hold`),
// for the finish's local relaxation of its last jams (finish.cpp).
#pragma once
#include <cstdint>
#include <vector>

#include "fill/centre_grid.hpp"
#include "pfill/engine/particle_engine.hpp"
#include "pfill/vec3.hpp"

namespace pfill {

/// A place's part in a relaxation around `places`: moving within `reach`
/// of one, held within `reach + hold` of one, else out (the engines' hold).
class NearParts {
 public:
  /// (`places` must outlive this.)
  NearParts(const std::vector<Vec3>& places, double reach, double hold);
  ParticleEngine::StepPart operator()(const Vec3& p) const;

 private:
  const std::vector<Vec3>& places_;
  double reach2_, outer2_;
  CentreGrid grid_;  // a cell of reach + hold: every place within it lies in the 27 around
};

struct NearRegion {
  std::vector<uint32_t> moving;  ///< indices into the particles, within `reach` of a place
  std::vector<uint32_t> held;    ///< the others within `reach + hold` of one
};

/// The particles whose centres lie within `reach` of one of `places`
/// (moving) and those within `reach + hold` of one but not moving (held),
/// each list in the particles' order.
NearRegion region_near(const std::vector<Particle>& particles, const std::vector<Vec3>& places, double reach,
                       double hold);

/// The particles of `region`, the moving ones first, as they are, then the
/// held ones with mass `held_mass`; all at rest, each with its index in
/// `particles` as its id (with_moved matches them by it).
std::vector<Particle> region_particles(const std::vector<Particle>& particles, const NearRegion& region,
                                       double held_mass);

/// `particles` after the region's relaxation: the others as they were, in
/// their order, then the moving ones that `moved` (region_particles'
/// spheres, relaxed) still holds, with all but their new positions from
/// `particles` (one missing from `moved`, which the wall took, is gone);
/// every velocity 0.
std::vector<Particle> with_moved(std::vector<Particle> particles, const NearRegion& region,
                                 const std::vector<Particle>& moved);

}  // namespace pfill
