/// @file local_view.hpp
/// @brief What the finish decides on in this process (issue 31): its own
/// particles, whole, and every other particle within a reach of its
/// sub-domain (the halo). One process (the OpenCL and reference engines,
/// LAMMPS at one rank): every particle is its own and there is no halo.
/// LAMMPS at P > 1 ranks: the rank's own atoms, plus the other ranks'
/// within `reach` of its sub-domain; so the finish's rounds (overlaps,
/// deletions, holes) need no gather of the whole set.
#pragma once
#include <cstdint>
#include <vector>

#include "pfill/engine/birth_view.hpp"
#include "pfill/engine/particle_engine.hpp"

namespace pfill {

struct LocalView {
  std::vector<Particle> particles;  ///< this process's own first, then the halo
  size_t own = 0;                   ///< how many of `particles` are this process's
  std::vector<size_t> indices;      ///< the engine's index of each own particle
  /// For every particle in view: a number that orders the particles alike
  /// on every process (LAMMPS: the tag; one process: the index). Ties go
  /// by it, so two processes that see the same pair decide it alike.
  std::vector<uint64_t> keys;
  /// Every process's sub-domain, in process order, and this process's
  /// place; empty: one process, which decides everywhere.
  std::vector<Box3> regions;
  int region = 0;

  bool complete() const { return regions.empty(); }
  bool is_own(size_t k) const { return k < own; }
  /// Whether this process decides what happens at p (a hole's sphere).
  bool decides(const Vec3& p) const { return complete() || owning_region(regions, p) == region; }
};

/// The view of one process: every particle its own, keys the indices.
inline LocalView whole_view(std::vector<Particle> particles) {
  LocalView v;
  v.own = particles.size();
  v.indices.resize(v.own);
  v.keys.resize(v.own);
  for (size_t i = 0; i < v.own; ++i) v.indices[i] = i, v.keys[i] = i;
  v.particles = std::move(particles);
  return v;
}

}  // namespace pfill
