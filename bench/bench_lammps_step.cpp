// The cost of one LAMMPS engine step on a real packing (docs/lammps_engine.md
// "A LAMMPS step's cost"): the spheres of a fill's output (PARTICLES, equal
// radii) in MESH's distance field, stepped as pass 1 steps (leapfrog with
// the dashpot; a share of the spheres moving at pass 1's newborn speeds, so
// lists are rebuilt as in pass 1) or as the finish relaxes (FIRE, the wall
// moved in). Steps run in chunks of 100 with a read of the records between,
// as the finish reads them; `held`: FIRE as the finish's relaxation of its
// last jams (ParticleEngine::hold), around 16 of the spheres (within 6 r
// moving, 3 r further held, the rest out). Prints ms a step (rank 0), the
// records' last kinetic energy and colliding pairs (to compare two builds'
// physics).
//   mpirun -np P build/bench/bench_lammps_step MESH PARTICLES [STEPS [pass|fire|held [SEED]]]
// With PFILL_LAMMPS_LOG=FILE, LAMMPS' own timing breakdown goes to FILE.
#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "fill/fill_plan.hpp"
#include "fill/near_region.hpp"
#include "pfill/boundary.hpp"
#include "pfill/engine/particle_engine.hpp"
#include "pfill/fill.hpp"
#include "pfill/lammps.hpp"
#include "pfill/mesh_io.hpp"
#include "pfill/particle_io.hpp"
#include "pfill/sdf.hpp"

using namespace pfill;
using Clock = std::chrono::steady_clock;

namespace {

/// The fill's engine parameters at its defaults (fill_plan.cpp), or the
/// finish's FIRE relaxation (finish.cpp) when `fire`.
EngineParams step_params(double r, bool fire) {
  const FillOptions o;
  FillPlan plan;
  plan.radius = plan.mean_radius = plan.max_radius = r;
  EngineParams p = plan_engine_params(plan, o);
  if (!fire) return p;
  const double shrink = 0.5 * 0.001 * r;  // the finish's spheres, smaller by half the bound
  p.births_at_speed = false;
  p.rest_distance = 2 * r * 1.001;
  p.restitution = 1, p.wall_restitution = 0, p.damping = 0;
  p.radius = r - shrink;
  p.max_radius = r * (1 + 1e-6);
  p.dt = 0.01 * derive_constants(p).tau;
  p.fire.on = true;
  p.fire.dt_max = 8;
  p.wall_offset = r * 1.1 - p.radius;
  return p;
}

ScalarGrid mesh_field(const std::string& mesh, double r) {
  Boundary boundary(load_mesh(mesh));
  SdfOptions so(0.33 * r);
  so.margin = 2 * r + 3 * so.spacing;
  return build_signed_distance_field(boundary, so);
}

}  // namespace

int main(int argc, char** argv) {
  if (!lammps_available() || argc < 3) {
    std::fprintf(stderr, "usage: mpirun -np P bench_lammps_step MESH PARTICLES [STEPS [pass|fire|held [SEED]]]\n");
    return 1;
  }
  const MpiWorld world = lammps_mpi_start();
  const int steps = argc > 3 ? std::atoi(argv[3]) : 1000;
  const std::string mode = argc > 4 ? argv[4] : "pass";
  const bool fire = mode == "fire" || mode == "held";
  const unsigned seed = argc > 5 ? static_cast<unsigned>(std::atoi(argv[5])) : 1;
  const ParticleSet set = read_particles(argv[2]);
  const double r = set.radii.at(0);
  const ScalarGrid field = mesh_field(argv[1], r);
  const EngineParams p = step_params(r, fire);
  std::unique_ptr<ParticleEngine> e = make_lammps_engine(p);
  e->share_field(field);
  // Pass 1: one sphere in 20 moving at a newborn's speed (0.3-0.6 of the top speed).
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1), s(0.3, 0.6);
  const double top = derive_constants(p).max_speed;
  std::vector<Particle> ps(set.size());
  for (size_t i = 0; i < ps.size(); ++i) {
    ps[i].position = set.positions[i];
    ps[i].radius = p.radius;
    ps[i].id = i + 1;
    Vec3 d{u(rng), u(rng), u(rng)};
    if (!fire && i % 20 == 0 && length(d) > 0) ps[i].velocity = d * (s(rng) * top / length(d));
  }
  e->add_particles(ps);
  std::vector<Vec3> places;
  for (size_t i = 0; mode == "held" && i < 16; ++i) places.push_back(ps[i * ps.size() / 16].position);
  size_t taking_part = ps.size();
  if (mode == "held") taking_part = e->hold(NearParts(places, 6 * r, 3 * r)).value_or(ps.size());
  e->run_steps(100);
  e->read_history();
  const auto t0 = Clock::now();
  const std::clock_t c0 = std::clock();  // this rank's CPU time: less swayed by other load than the wall
  std::vector<StepRecord> h;
  for (int done = 0; done < steps; done += 100) {
    e->run_steps(100);
    h = e->read_history();
  }
  const double t = std::chrono::duration<double>(Clock::now() - t0).count();
  const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  if (world.rank == 0 && !h.empty())
    std::printf("%s N %zu (%zu moving or held), P %d, %d steps: %.3f s, %.3f ms a step (rank 0 CPU %.3f ms); last "
                "step: ke %.6g, colliding %u, flagged %u\n",
                mode.c_str(), e->size(), taking_part, world.size, steps, t, 1e3 * t / steps, 1e3 * cpu / steps,
                h.back().kinetic_energy, h.back().colliding_pairs, h.back().flagged);
  return 0;
}
