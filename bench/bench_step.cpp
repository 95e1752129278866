// bench_step: speed of the engine's whole update (cell lists, pairs,
// contacts, wall, integration, per-step scalars) on the chosen OpenCL device
// (PFILL_DEVICE). Large systems: particle-steps per second at N = 1e4, 1e5
// (and 1e6 with --big) at packing fraction 0.6 in a box, rc = 2.5 sigma and
// purely repulsive. Small systems: steps per second at N = 500, 1000, 4000,
// purely repulsive, with the per-step history read back every 50 steps.
// Per-kernel times come from a second, profiled run. Text on stdout, JSON
// with --json FILE.
//
//   bench_step [--big] [--quick] [--only N] [--json FILE]
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pfill/device/device.hpp"
#include "pfill/engine/engine.hpp"
#include "pfill/error.hpp"

using namespace pfill;
using Clock = std::chrono::steady_clock;

namespace {

constexpr double kRadius = 0.5;
constexpr double kPacking = 0.6;

// The SDF of the box [-h, h]^3 sampled at `spacing`.
ScalarGrid box_field(double h, double spacing) {
  ScalarGrid g;
  const int n = static_cast<int>(std::ceil(2 * h / spacing)) + 5;
  g.spacing = spacing;
  g.origin = Vec3(-1, -1, -1) * (h + 2 * spacing);
  g.dims = {n, n, n};
  g.values.resize(static_cast<size_t>(n) * n * n);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const Vec3 p = g.point(i, j, k);
        const Vec3 q{std::fabs(p.x) - h, std::fabs(p.y) - h, std::fabs(p.z) - h};
        const Vec3 out{std::max(q.x, 0.0), std::max(q.y, 0.0), std::max(q.z, 0.0)};
        g.values[g.index(i, j, k)] =
            static_cast<float>(length(out) + std::min(std::max(q.x, std::max(q.y, q.z)), 0.0));
      }
  return g;
}

// N spheres of radius 0.5 on an FCC lattice filling a box at packing 0.6
// (nearest neighbours 1.07 apart: no overlap), small random velocities.
// Returns the box half-size.
double fcc_system(size_t n, std::vector<Particle>& out) {
  const double volume = n * (4.0 / 3.0) * M_PI * std::pow(kRadius, 3) / kPacking;
  const double side = std::cbrt(volume);
  const int cells = static_cast<int>(std::ceil(std::cbrt(n / 4.0)));
  const double a = side / cells;  // FCC cell edge
  const double h = side / 2 + kRadius;  // walls one radius beyond the lattice's outer centres
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> vel(-0.5, 0.5);
  const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  out.clear();
  for (int k = 0; k < cells && out.size() < n; ++k)
    for (int j = 0; j < cells && out.size() < n; ++j)
      for (int i = 0; i < cells && out.size() < n; ++i)
        for (const auto& b : basis) {
          if (out.size() >= n) break;
          Particle p;
          p.position = Vec3(i + b[0] + 0.25, j + b[1] + 0.25, k + b[2] + 0.25) * a - Vec3(1, 1, 1) * (side / 2);
          p.velocity = {vel(rng), vel(rng), vel(rng)};
          p.radius = kRadius;
          out.push_back(p);
        }
  return h;
}

struct Case {
  size_t n;
  double cutoff_sigma;  // 0: purely repulsive
  bool small;           // steps/s with the history read every 50 steps
  bool births = false;  // also one birth a step (and one removal, to keep N), as the fill does
};

// CPU seconds used by the whole process (all PoCL threads): on a shared
// machine this is steadier than wall time.
double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

nlohmann::json run_case(Device& device, Device& profiled, const Case& c, bool quick) {
  EngineParams p;
  p.radius = kRadius;
  p.cutoff_sigma = c.cutoff_sigma;
  p.restitution = 0.5;
  p.wall_restitution = 0.5;
  std::vector<Particle> ps;
  const double h = fcc_system(c.n, ps);
  const ScalarGrid field = box_field(h, kRadius / 2);

  // Births: two lattice sites A and B are left empty; each step the newest
  // particle is removed and a newcomer (at rest) is born at the other site.
  std::vector<Particle> sites;
  if (c.births) {
    sites = {ps[0], ps[1]};
    for (auto& q : sites) q.velocity = {};
    ps.erase(ps.begin(), ps.begin() + 2);
    ps.push_back(sites[0]);
  }
  Engine engine(device, p);
  engine.set_field(field);
  engine.add_particles(ps);
  engine.run_steps(10);  // warm-up: kernels compiled for this size, caches filled
  engine.read_history();

  // Steps per trial so that a trial takes ~0.3 s (quick: ~0.1 s).
  auto t0 = Clock::now();
  engine.run_steps(5);
  engine.finish();
  const double probe = std::chrono::duration<double>(Clock::now() - t0).count() / 5;
  const double target = quick ? 0.1 : 0.3;
  size_t steps = std::max<size_t>(10, static_cast<size_t>(target / std::max(probe, 1e-7)));
  if (c.small) steps = (steps + 49) / 50 * 50;
  std::vector<double> rates, cpu_per_step;
  uint32_t overflow = 0, flagged = 0;
  double ke = 0;
  for (int trial = 0; trial < (quick ? 3 : 5); ++trial) {
    engine.read_history();
    const auto start = Clock::now();
    const double cpu_start = process_cpu_seconds();
    if (c.small) {
      for (size_t s = 0; s < steps; s += 50) {
        if (c.births) {
          for (size_t b = 0; b < 50; ++b) {  // the newest particle leaves, a newcomer is born at the other site
            engine.remove_particles({engine.size() - 1});
            engine.add_particle(sites[(s + b) % 2]);
            engine.run_steps(1);
          }
        } else {
          engine.run_steps(50);
        }
        for (const auto& r : engine.read_history()) {  // what the stopping tests read
          overflow += r.cell_overflow;
          flagged += r.flagged;
          ke = r.kinetic_energy;
        }
      }
    } else {
      engine.run_steps(steps);
      engine.finish();
    }
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    rates.push_back(steps / seconds);
    cpu_per_step.push_back((process_cpu_seconds() - cpu_start) / steps);
  }
  for (const auto& r : engine.read_history()) {
    overflow += r.cell_overflow;
    flagged += r.flagged;
    ke = r.kinetic_energy;
  }
  const double steps_per_s = median(rates);

  // Per-kernel times from a profiled engine on the same device.
  Engine prof(profiled, p);
  prof.set_field(field);
  prof.add_particles(ps);
  prof.run_steps(10);
  prof.kernel_times();
  const size_t prof_steps = std::min<size_t>(steps, 200);
  prof.run_steps(prof_steps);
  nlohmann::json kernels = nlohmann::json::object();
  for (const auto& [name, seconds] : prof.kernel_times()) kernels[name] = seconds / prof_steps * 1e6;

  nlohmann::json j;
  j["n"] = c.n;
  j["cutoff"] = c.cutoff_sigma > 0 ? "2.5 sigma" : "repulsive";
  j["mode"] = c.births ? "steps/s, history read every 50 steps, one birth and one removal a step (N-1 particles)"
                       : c.small ? "steps/s, history read every 50 steps" : "particle-steps/s, no reads";
  j["steps_per_trial"] = steps;
  j["steps_per_second"] = steps_per_s;
  j["particle_steps_per_second"] = steps_per_s * c.n;
  j["us_per_step"] = 1e6 / steps_per_s;
  j["cpu_us_per_step"] = 1e6 * median(cpu_per_step);  // all threads together
  j["kernel_us_per_step"] = kernels;
  j["cell_capacity"] = engine.constants().cell_capacity;
  j["cell_overflow_hits"] = overflow;
  j["flagged"] = flagged;
  j["final_kinetic_energy"] = ke;
  return j;
}

}  // namespace

int main(int argc, char** argv) {
  bool big = false, quick = false;
  size_t only = 0;
  std::string json_path;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--big")) big = true;
    else if (!std::strcmp(argv[i], "--quick")) quick = true;
    else if (!std::strcmp(argv[i], "--json") && i + 1 < argc) json_path = argv[++i];
    else if (!std::strcmp(argv[i], "--only") && i + 1 < argc) only = std::strtoul(argv[++i], nullptr, 10);
    else {
      std::fprintf(stderr, "usage: bench_step [--big] [--quick] [--only N] [--json FILE]\n");
      return 2;
    }
  }
  try {
    Device device;
    Device profiled("", true);
    std::printf("device: %s (%s)\n", device.info().name.c_str(), device.info().platform.c_str());
    std::vector<Case> cases;
    std::vector<size_t> large = {10000, 100000};
    if (big) large.push_back(1000000);
    for (size_t n : large)
      for (double rc : {2.5, 0.0}) cases.push_back({n, rc, false});
    for (size_t n : {500, 1000, 4000}) cases.push_back({n, 0.0, true});
    cases.push_back({4000, 0.0, true, true});
    nlohmann::json all;
    all["device"] = device.info().name;
    all["platform"] = device.info().platform;
    all["compute_units"] = device.info().compute_units;
    for (const Case& c : cases) {
      if (only && c.n != only) continue;
      const nlohmann::json j = run_case(device, profiled, c, quick);
      std::printf("N=%-6zu%s %-10s %10.0f steps/s %12.4g particle-steps/s %9.1f us/step %9.1f cpu-us/step  kernels(us/step):",
                  c.n, c.births ? "+b" : "  ", j["cutoff"].get<std::string>().c_str(), j["steps_per_second"].get<double>(),
                  j["particle_steps_per_second"].get<double>(), j["us_per_step"].get<double>(),
                  j["cpu_us_per_step"].get<double>());
      for (const auto& [k, v] : j["kernel_us_per_step"].items()) std::printf(" %s %.1f", k.c_str(), v.get<double>());
      std::printf("%s\n", j["cell_overflow_hits"].get<uint32_t>() ? "  CELL OVERFLOW" : "");
      std::fflush(stdout);
      all["cases"].push_back(j);
    }
    if (!json_path.empty()) {
      std::ofstream(json_path) << all.dump(2) << "\n";
      std::printf("wrote %s\n", json_path.c_str());
    }
  } catch (const Error& e) {
    std::fprintf(stderr, "bench_step: %s\n", e.what());
    return 1;
  }
  return 0;
}
