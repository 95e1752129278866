// The price of driving LAMMPS through its library per birth wave
// (docs/lammps_engine.md): N particles in a ball on the LAMMPS engine, then
//   - W waves of `every` steps, each as the fill runs one: a few births,
//     the steps (one `run ... pre yes`), the records, all positions read;
//   - the same steps as one `run` (no births, no reads).
// The difference a wave is the library's overhead (set-up of a run with
// re-neighbouring, the births, the gather). Run under mpirun for P ranks:
//   mpirun -np P build/bench/bench_lammps_wave [N] [waves] [every]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "pfill/engine/particle_engine.hpp"
#include "pfill/lammps.hpp"

using namespace pfill;
using Clock = std::chrono::steady_clock;

int main(int argc, char** argv) {
  if (!lammps_available()) {
    std::fprintf(stderr, "this pfill was built without LAMMPS\n");
    return 1;
  }
  const MpiWorld world = lammps_mpi_start();
  const size_t n = argc > 1 ? std::strtoul(argv[1], nullptr, 10) : 16000;
  const int waves = argc > 2 ? std::atoi(argv[2]) : 20;
  const int every = argc > 3 ? std::atoi(argv[3]) : 48;
  // A ball holding n spheres at about 0.55 of its volume.
  const double r = 0.01, R = r * std::cbrt(n / 0.55);
  EngineParams p;
  p.radius = r;
  p.max_radius = r * (1 + 1e-6);
  p.dt = 0.01 * derive_constants(p).tau;
  p.max_step_fraction = 0.1;
  ScalarGrid field = sampled_grid(R + 4 * r, 0.33 * r, [R](const Vec3& q) { return length(q) - R; });
  std::unique_ptr<ParticleEngine> e = make_lammps_engine(p);
  e->share_field(field);
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Particle> ps;
  const double a = 2.2 * r;
  for (double x = -R; x < R; x += a)
    for (double y = -R; y < R; y += a)
      for (double z = -R; z < R; z += a)
        if (std::sqrt(x * x + y * y + z * z) < R - 1.5 * r) {
          Particle q;
          q.position = {x, y, z};
          q.velocity = Vec3{u(rng), u(rng), u(rng)} * (0.3 * derive_constants(p).max_speed);
          q.radius = r;
          q.id = ps.size() + 1;
          ps.push_back(q);
        }
  e->add_particles(ps);
  e->run_steps(200);
  e->read_history();
  auto t0 = Clock::now();
  for (int w = 0; w < waves; ++w) {
    e->run_steps(static_cast<size_t>(every));
    e->read_history();
    std::vector<Particle> now = e->read_particles();
    // A wave's births: where a particle is, nudged (the fill tests room first).
    std::vector<size_t> gone;
    std::vector<Particle> born;
    for (size_t k = 0; k < 20 && k < now.size(); ++k) {
      gone.push_back(k * 37 % now.size());
      Particle q = now[k * 37 % now.size()];
      q.id = 1000000 + static_cast<uint64_t>(w) * 100 + k;
      born.push_back(q);
    }
    e->remove_particles(gone);
    e->add_particles(born);
  }
  const double waved = std::chrono::duration<double>(Clock::now() - t0).count();
  auto t1 = Clock::now();
  e->run_steps(static_cast<size_t>(waves * every));
  e->read_history();
  const double plain = std::chrono::duration<double>(Clock::now() - t1).count();
  if (world.rank == 0)
    std::printf("N %zu, P %d, %d waves of %d steps: %.3f s in waves, %.3f s as one run; %.2f ms a step, "
                "%.2f ms overhead a wave (%.1f%% of a wave)\n",
                e->size(), world.size, waves, every, waved, plain, 1e3 * plain / (waves * every),
                1e3 * (waved - plain) / waves, 100 * (waved - plain) / waved);
  return 0;
}
