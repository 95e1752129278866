// Fixtures the LAMMPS engine's tests share (test_lammps_engine.cpp, test_lammps_fire.cpp, test_lammps_wall.cpp).
#pragma once
#include <cstdint>
#include <random>
#include <vector>

#include "pfill/engine/particle_engine.hpp"
#include "pfill/grid.hpp"

namespace pfill::test {

/// Spheres of radius 0.05 with a dashpot and a damped, capped step: the
/// engine tests' parameters (test_lammps_engine.cpp, test_lammps_wall.cpp).
inline EngineParams small_params() {
  EngineParams p;
  p.radius = 0.05;
  p.max_radius = p.radius * (1 + 1e-6);
  p.restitution = 0.5;
  p.wall_restitution = 0.5;
  p.damping = 0.5;
  p.dt = 0.01 * derive_constants(p).tau;
  p.max_step_fraction = 0.1;
  return p;
}

/// A ball of radius R at the origin as a signed distance grid.
inline ScalarGrid ball_field(double R, double spacing) {
  return sampled_grid(R + 0.2, spacing, [R](const Vec3& p) { return length(p) - R; });
}

/// Spheres of radius 0.05 on a lattice of `spacing` inside the ball of
/// radius R (centres 0.06 inside), each moved by up to `jitter` of the
/// spacing and moving at up to 0.2; ids from `first_id` on.
inline std::vector<Particle> jittered_lattice(double R, double spacing, uint64_t seed, double jitter,
                                              uint64_t first_id) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Particle> ps;
  uint64_t id = first_id;
  for (double x = -R; x <= R; x += spacing)
    for (double y = -R; y <= R; y += spacing)
      for (double z = -R; z <= R; z += spacing) {
        Particle p;
        p.position = Vec3{x, y, z} + Vec3{u(rng), u(rng), u(rng)} * (jitter * spacing);
        if (length(p.position) > R - 0.06) continue;
        p.velocity = Vec3{u(rng), u(rng), u(rng)} * 0.2;
        p.radius = 0.05;
        p.id = id++;
        ps.push_back(p);
      }
  return ps;
}

}  // namespace pfill::test
