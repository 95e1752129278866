/// @file particle_share.hpp
/// @brief A packing held in parts (issue 31): after a fill on the LAMMPS
/// engine at P > 1 ranks, each process holds its own spheres (those in its
/// sub-domain) and no process all of them. What the fill's exact check and
/// the output need across the parts: a halo of the other processes' spheres
/// near this one's region, and a gather of the whole to one process. One
/// process (the OpenCL engine): its spheres are the whole, there is no halo.
#pragma once
#include <memory>
#include <vector>

#include "pfill/engine/process_group.hpp"
#include "pfill/particles.hpp"
#include "pfill/vec3.hpp"

namespace pfill {

/// Which processes hold a packing's parts and where each part lies.
struct ParticleShare {
  std::shared_ptr<ProcessGroup> group = std::make_shared<ProcessGroup>();
  /// Every process's region, in process order (its own spheres' centres
  /// lie in it, or did before the exact check moved them a little), and
  /// this process's; empty: one process, whose spheres are all.
  std::vector<Box3> regions;
  int region = 0;

  bool complete() const { return regions.empty(); }
  /// This process's region; nullptr when it holds every sphere.
  const Box3* mine() const { return complete() ? nullptr : &regions[static_cast<size_t>(region)]; }
  /// Whether a sphere placed at p (a hole's) is this process's own.
  bool owns(const Vec3& p) const;
};

/// The other processes' spheres whose centres lie within `reach` of this
/// process's region (centres, radii, ids; no colours, no velocities), each
/// with `width` values of `own_extra` (width values per own sphere), given
/// back in `extra`. Collective. One process: none.
ParticleSet halo_of(const ParticleShare& share, const ParticleSet& own, double reach,
                    const std::vector<double>& own_extra = {}, size_t width = 0, std::vector<double>* extra = nullptr);

/// `own` then `halo`: centres, radii and ids (own's ids as ParticleSet::id
/// gives them), what a process's searches over its region look at.
ParticleSet own_and_halo(const ParticleSet& own, const ParticleSet& halo);

/// Every process's `own`, whole, in the order of the ids: on the first
/// process only (the others get an empty set), or with `everywhere` on
/// every process. Colours and velocities go along where the sets have
/// them. Collective; one process: `own`, as it is.
ParticleSet gather_particles(ProcessGroup& group, const ParticleSet& own, bool everywhere = false);

}  // namespace pfill
