// bench_step: speed of the engine's whole update (cell lists, pairs,
// contacts, wall, integration, per-step scalars) on the chosen OpenCL device
// (PFILL_DEVICE). Large systems: particle-steps per second at N = 1e4, 1e5
// (and 1e6 with --big) at packing fraction 0.6 in a box, rc = 2.5 sigma and
// purely repulsive. Small systems: steps per second at N = 500, 1000, 4000,
// purely repulsive, with the per-step history read back every 50 steps.
// Per-kernel times come from a second, profiled run. The fill regime
// (run_fill_case; --fill runs only it): growth from 0 to 4,000 by births
// at fast speeds, as a fill's pass 1 does. Text on stdout, JSON with
// --json FILE. With --field-image every case runs twice, the wall field
// as a buffer (the default) and as a 3D image (EngineParams::field_image),
// printed one line after the other. The lattice is renumbered along the
// cells first (Engine::sort_by_cells, as a large system should be; --no-sort
// keeps the lattice's row order; --cutoff lj or repulsive runs only the
// large cases of that cutoff). Each line also gives the share of steps
// that rebuilt the neighbour lists and the update's time on those and on
// the others. --work-group, --force-buffers, --newton (on, off),
// --pair-queue (on, off), --inner-lists (on, off), --inner-skin (sigma),
// --step-form (cpu, gpu) and --skin (every case's list skin, in sigma) set
// EngineParams' values. --radii-ratio K (K >= 2; or K1,K2,...) adds after each large case
// the same case with unequal spheres at the same packing (mixed_system):
// half the spheres (by number) of radius 0.5, half of 0.5 K, the large
// ones on an FCC lattice and the small ones in its octahedral holes
// (K >= 2; the wall field sampled K times coarser), so that the line below
// the equal spheres' compares the cost per particle-step (printed as a
// ratio, of wall and of CPU time, and kept in the JSON as cost_vs_equal).
//
//   bench_step [--radii-ratio K] [--big] [--quick] [--fill] [--skin S] [--only N] [--cutoff lj|repulsive] [--field-image] [--work-group W] [--force-buffers B] [--newton on|off] [--pair-queue on|off] [--inner-lists on|off] [--inner-skin S] [--step-form cpu|gpu] [--no-sort] [--json FILE]
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pfill/device/device.hpp"
#include "pfill/engine/engine.hpp"
#include "pfill/error.hpp"
#include "pfill/fill.hpp"

#include "bench_systems.hpp"

using namespace pfill;
using bench::kRadius;
using bench::box_field;
using bench::fcc_system;
using Clock = std::chrono::steady_clock;

namespace {

// The settings from the command line (--work-group, --force-buffers,
// --newton, --step-form); each case starts from them.
EngineParams tuning;
bool sort_cells = true;                          // Engine::sort_by_cells after the bulk addition (--no-sort: off)

// Half of n spheres of radius kRadius ratio on an FCC lattice, half of
// kRadius in its octahedral holes (one a lattice site: the cell's centre
// and its edges' midpoints), at packing kPacking in a box; small random
// velocities. Needs ratio >= 2 (a small sphere fits its hole: the hole's
// room is 0.52 of the large radius at ratio 4, 0.58 at ratio 2). Returns
// the box half-size.
double mixed_system(size_t n, double ratio, std::vector<Particle>& out) {
  const double big = kRadius * ratio;
  const size_t n_big = (n + 1) / 2, n_small = n / 2;
  const double volume =
      (n_big * std::pow(big, 3) + n_small * std::pow(kRadius, 3)) * (4.0 / 3.0) * M_PI / bench::kPacking;
  const double side = std::cbrt(volume);
  const int cells = static_cast<int>(std::ceil(std::cbrt(n_big / 4.0)));
  const double a = side / cells;  // FCC cell edge
  const double h = side / 2 + big;
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> vel(-0.5, 0.5);
  const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  const double holes[4][3] = {{0.5, 0.5, 0.5}, {0.5, 0, 0}, {0, 0.5, 0}, {0, 0, 0.5}};
  out.clear();
  size_t bigs = 0, smalls = 0;
  for (int k = 0; k < cells; ++k)
    for (int j = 0; j < cells; ++j)
      for (int i = 0; i < cells; ++i)
        for (int q = 0; q < 4; ++q) {
          for (int kind = 0; kind < 2; ++kind) {
            const double* b = kind == 0 ? basis[q] : holes[q];
            size_t& count = kind == 0 ? bigs : smalls;
            if (count >= (kind == 0 ? n_big : n_small)) continue;
            Particle p;
            p.position = Vec3(i + b[0] + 0.25, j + b[1] + 0.25, k + b[2] + 0.25) * a - Vec3(1, 1, 1) * (side / 2);
            p.velocity = {vel(rng), vel(rng), vel(rng)};
            p.radius = kind == 0 ? big : kRadius;
            out.push_back(p);
            ++count;
          }
        }
  return h;
}

// The command line's settings for spheres of kRadius, restitution 0.5.
EngineParams case_params(bool field_image) { return bench::sphere_params(tuning, field_image); }

struct Case {
  size_t n;
  double cutoff_sigma;  // 0: purely repulsive
  bool small;           // steps/s with the history read every 50 steps
  bool births = false;  // also one birth a step (and one removal, to keep N), as the fill does
  double radii_ratio = 1;  // > 1: mixed_system, half the spheres this much larger
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

nlohmann::json run_case(Device& device, Device& profiled, const Case& c, bool quick, bool field_image) {
  EngineParams p = case_params(field_image);
  p.cutoff_sigma = c.cutoff_sigma;
  std::vector<Particle> ps;
  const double h = c.radii_ratio > 1 ? mixed_system(c.n, c.radii_ratio, ps) : fcc_system(c.n, ps);
  if (c.radii_ratio > 1) p.max_radius = kRadius * c.radii_ratio;
  const ScalarGrid field = box_field(h, kRadius / 2 * c.radii_ratio);

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
  if (sort_cells) engine.sort_by_cells();
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
  uint64_t timed_steps = 0, timed_rebuilds = 0;  // over the timed trials
  double ke = 0;
  for (int trial = 0; trial < (quick ? 3 : 5); ++trial) {
    for (const auto& r : engine.read_history()) timed_rebuilds += trial > 0 && r.lists_rebuilt;
    timed_steps += steps;
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
          timed_rebuilds += r.lists_rebuilt;
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
    timed_rebuilds += r.lists_rebuilt;
    overflow += r.cell_overflow;
    flagged += r.flagged;
    ke = r.kinetic_energy;
  }
  const double steps_per_s = median(rates);

  // Per-kernel times from a profiled engine on the same device.
  Engine prof(profiled, p);
  prof.set_field(field);
  prof.add_particles(ps);
  if (sort_cells) prof.sort_by_cells();
  prof.run_steps(10);
  prof.kernel_times();
  prof.read_history();
  // Step by step, so that each step's update time pairs with whether it
  // rebuilt the neighbour lists (the costly part on a rebuild step); the
  // history is read once at the end, as a run would.
  const size_t prof_steps = std::min<size_t>(steps, 200);
  std::map<std::string, double> totals;
  std::vector<double> updates;
  for (size_t s = 0; s < prof_steps; ++s) {
    prof.run_steps(1);
    const auto times = prof.kernel_times();
    for (const auto& [name, seconds] : times) totals[name] += seconds;
    double update = 0;  // the update proper: pair_forces (CPU devices) and advance
    for (const char* name : {"pair_forces", "advance"})
      if (times.count(name)) update += times.at(name);
    updates.push_back(update);
  }
  const std::vector<StepRecord> records = prof.read_history();
  double update_rebuild = 0, update_other = 0;
  size_t rebuilds = 0;
  std::vector<double> others;
  for (size_t s = 0; s < prof_steps && s < records.size(); ++s) {
    if (records[s].lists_rebuilt) {
      ++rebuilds;
      update_rebuild += updates[s];
    } else {
      update_other += updates[s];
      others.push_back(updates[s]);
    }
  }
  // The fastest tenth of the other steps: on a shared machine the least
  // disturbed ones, so the steadiest figure for comparing kernel variants.
  std::sort(others.begin(), others.end());
  const double other_p10 = others.empty() ? 0.0 : others[others.size() / 10];
  nlohmann::json kernels = nlohmann::json::object();
  for (const auto& [name, seconds] : totals) kernels[name] = seconds / prof_steps * 1e6;

  nlohmann::json j;
  j["n"] = c.n;
  j["radii_ratio"] = c.radii_ratio;
  j["list_capacity"] = engine.constants().list_capacity;
  j["cutoff"] = c.cutoff_sigma > 0 ? "2.5 sigma" : "repulsive";
  j["skin_sigma"] = engine.params().skin_sigma;  // (an automatic skin resolved)
  j["sorted_by_cells"] = sort_cells;
  j["mode"] = c.births ? "steps/s, history read every 50 steps, one birth and one removal a step (N-1 particles)"
                       : c.small ? "steps/s, history read every 50 steps" : "particle-steps/s, no reads";
  j["steps_per_trial"] = steps;
  j["steps_per_second"] = steps_per_s;
  j["particle_steps_per_second"] = steps_per_s * c.n;
  j["us_per_step"] = 1e6 / steps_per_s;
  j["cpu_us_per_step"] = 1e6 * median(cpu_per_step);  // all threads together
  j["kernel_us_per_step"] = kernels;
  j["rebuild_share"] = static_cast<double>(timed_rebuilds) / timed_steps;  // timed run
  j["rebuild_share_profiled"] = static_cast<double>(rebuilds) / prof_steps;
  j["update_us_rebuild_step"] = rebuilds ? update_rebuild / rebuilds * 1e6 : 0.0;
  j["update_us_other_step"] = rebuilds < prof_steps ? update_other / (prof_steps - rebuilds) * 1e6 : 0.0;
  j["update_us_other_step_p10"] = other_p10 * 1e6;
  j["cell_capacity"] = engine.constants().cell_capacity;
  j["cell_overflow_hits"] = overflow;
  j["flagged"] = flagged;
  j["final_kinetic_energy"] = ke;
  return j;
}

// The fill's regime (src/fill/fill.cpp with its defaults): a sphere
// field, two birth sites, a birth attempt at each every 3 steps when no
// centre is within one radius of the site (in the snapshot read every 8
// steps, plus the newborns since then, flying straight), newborns at
// FillOptions' speeds (birth_speed_min to _max of the top speed, 0.1
// sigma a step, dt 0.01 tau) and skin, purely repulsive, growing to
// `target` particles, renumbered along the cells every
// FillOptions::sort_every steps. Reports steps/s over the whole
// growth, the share of steps that rebuilt the neighbour lists, and the
// per-kernel times from a second, profiled run of the same growth.
nlohmann::json run_fill_case(Device& device, Device& profiled, size_t target, double skin_sigma, bool field_image) {
  EngineParams p = case_params(field_image);
  p.cutoff_sigma = 0;
  p.max_step_fraction = 0.1;
  p.dt = 0.01 * derive_constants(p).tau;
  p.skin_sigma = skin_sigma;
  // Sphere holding `target` spheres at packing 0.6.
  const double R = std::cbrt(3 * target * (4.0 / 3.0) * M_PI * std::pow(kRadius, 3) / (0.6 * 4 * M_PI));
  const ScalarGrid field = sampled_grid(R, kRadius / 2, [R](const Vec3& x) { return length(x) - R; });
  const Vec3 sites[2] = {{-R / 2, 0, 0}, {R / 2, 0, 0}};
  const uint64_t step_cap = 40 * target;

  struct Outcome {
    double seconds = 0;
    uint64_t steps = 0, rebuilds = 0;
    size_t n = 0;
    uint32_t overflow = 0;
  };
  auto grow = [&](Engine& engine) {
    Outcome o;
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> uni(0, 1);
    std::normal_distribution<double> gauss(0, 1);
    const double top = engine.constants().max_speed, dt = engine.constants().dt;
    std::vector<Vec3> snapshot;
    struct Newborn { Vec3 x, v; uint64_t step; };
    std::vector<Newborn> newborns;
    const auto start = Clock::now();
    while (engine.size() < target && engine.steps_done() < step_cap) {
      if (engine.steps_done() % static_cast<uint64_t>(FillOptions{}.sort_every) == 0) engine.sort_by_cells();
      for (int s = 0; s < 8; ++s) {
        if (engine.steps_done() % 3 == 0)
          for (const Vec3& site : sites) {
            if (engine.size() >= target) break;
            bool room = true;
            for (const Vec3& q : snapshot) room = room && length(q - site) >= 2 * kRadius * 0.5;
            for (const Newborn& b : newborns)
              room = room && length(b.x + b.v * (dt * (engine.steps_done() - b.step)) - site) >= 2 * kRadius * 0.5;
            if (!room) continue;
            Vec3 dir;
            do dir = {gauss(rng), gauss(rng), gauss(rng)}; while (length(dir) < 1e-9);
            Particle b;
            b.position = site;
            b.radius = kRadius;
            const FillOptions fo;
            b.velocity = dir / length(dir) * (top * (fo.birth_speed[0] + (fo.birth_speed[1] - fo.birth_speed[0]) * uni(rng)));
            engine.add_particle(b);
            newborns.push_back({b.position, b.velocity, engine.steps_done()});
          }
        engine.run_steps(1);
      }
      for (const StepRecord& r : engine.read_history()) {
        o.rebuilds += r.lists_rebuilt;
        o.overflow += r.cell_overflow;
      }
      const auto flagged = engine.flagged_particles();
      if (!flagged.empty()) {
        engine.clear_flags();
        engine.remove_particles(flagged);
      }
      snapshot.clear();
      for (const Particle& q : engine.read_particles()) snapshot.push_back(q.position);
      newborns.clear();
    }
    o.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    o.steps = engine.steps_done();
    o.n = engine.size();
    return o;
  };
  Engine engine(device, p);
  engine.set_field(field);
  const Outcome o = grow(engine);
  Engine prof(profiled, p);
  prof.set_field(field);
  const Outcome po = grow(prof);
  nlohmann::json kernels = nlohmann::json::object();
  for (const auto& [name, seconds] : prof.kernel_times()) kernels[name] = seconds / po.steps * 1e6;

  nlohmann::json j;
  j["n"] = o.n;
  j["cutoff"] = "repulsive";
  j["mode"] = "fill regime: growth from 0 to N, births at 2 sites every 3 steps at 0.5-1 of the top speed, "
              "history and positions read every 8 steps";
  j["steps"] = o.steps;
  j["seconds"] = o.seconds;
  j["steps_per_second"] = o.steps / o.seconds;
  j["us_per_step"] = 1e6 * o.seconds / o.steps;
  j["skin_sigma"] = skin_sigma;
  j["rebuild_share"] = static_cast<double>(o.rebuilds) / o.steps;
  j["kernel_us_per_step"] = kernels;
  j["cell_overflow_hits"] = o.overflow;
  return j;
}

}  // namespace

int main(int argc, char** argv) {
  bool big = false, quick = false, fill_only = false, field_image = false;
  double skin = 0;  // --skin: every case's; 0: EngineParams' default, and FillOptions' for the fill case
  size_t only = 0;
  std::vector<double> radii_ratios;  // --radii-ratio K[,K2...]: also each large case with unequal spheres
  std::string cutoff_only;  // --cutoff: "lj" (2.5 sigma) or "repulsive"; empty: both
  std::string json_path;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--big")) big = true;
    else if (!std::strcmp(argv[i], "--quick")) quick = true;
    else if (!std::strcmp(argv[i], "--fill")) fill_only = true;
    else if (!std::strcmp(argv[i], "--field-image")) field_image = true;
    else if (!std::strcmp(argv[i], "--skin") && i + 1 < argc) tuning.skin_sigma = skin = std::strtod(argv[++i], nullptr);
    else if (!std::strcmp(argv[i], "--work-group") && i + 1 < argc) tuning.work_group = std::strtoul(argv[++i], nullptr, 10);
    else if (!std::strcmp(argv[i], "--force-buffers") && i + 1 < argc)
      tuning.force_buffers = std::strtoul(argv[++i], nullptr, 10);
    else if (!std::strcmp(argv[i], "--newton") && i + 1 < argc)
      tuning.newton = std::strcmp(argv[++i], "off") == 0 ? Newton::off : Newton::on;
    else if (!std::strcmp(argv[i], "--pair-queue") && i + 1 < argc)
      tuning.pair_queue = std::strcmp(argv[++i], "off") == 0 ? PairQueue::off : PairQueue::on;
    else if (!std::strcmp(argv[i], "--inner-lists") && i + 1 < argc)
      tuning.inner_lists = std::strcmp(argv[++i], "off") == 0 ? InnerLists::off : InnerLists::on;
    else if (!std::strcmp(argv[i], "--inner-skin") && i + 1 < argc)
      tuning.inner_skin_sigma = std::strtod(argv[++i], nullptr);
    else if (!std::strcmp(argv[i], "--step-form") && i + 1 < argc)
      tuning.step_form = std::strcmp(argv[++i], "gpu") == 0 ? StepForm::gpu : StepForm::cpu;
    else if (!std::strcmp(argv[i], "--no-sort")) sort_cells = false;
    else if (!std::strcmp(argv[i], "--json") && i + 1 < argc) json_path = argv[++i];
    else if (!std::strcmp(argv[i], "--only") && i + 1 < argc) only = std::strtoul(argv[++i], nullptr, 10);
    else if (!std::strcmp(argv[i], "--cutoff") && i + 1 < argc) cutoff_only = argv[++i];
    else if (!std::strcmp(argv[i], "--radii-ratio") && i + 1 < argc && std::strtod(argv[i + 1], nullptr) >= 2) {
      for (const char* at = argv[++i]; *at;) {  // K or K1,K2,...
        char* end = nullptr;
        const double k = std::strtod(at, &end);
        if (end == at || !(k >= 2)) break;
        radii_ratios.push_back(k);
        at = *end == ',' ? end + 1 : end;
      }
    } else {
      std::fprintf(stderr, "usage: bench_step [--radii-ratio K[,K2...] (each >= 2)] [--big] [--quick] [--fill] [--skin S] [--only N] [--cutoff lj|repulsive] [--field-image] [--work-group W] [--force-buffers B] [--newton on|off] [--pair-queue on|off] [--inner-lists on|off] [--inner-skin S] [--step-form cpu|gpu] [--no-sort] [--json FILE]\n");
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
      for (double rc : {2.5, 0.0}) {
        cases.push_back({n, rc, false});
        for (double k : radii_ratios) cases.push_back({n, rc, false, false, k});
      }
    for (size_t n : {500, 1000, 4000}) cases.push_back({n, 0.0, true});
    cases.push_back({4000, 0.0, true, true});
    nlohmann::json all;
    all["device"] = device.info().name;
    all["platform"] = device.info().platform;
    all["compute_units"] = device.info().compute_units;
    std::vector<bool> fields = {false};  // field_image settings to run
    if (field_image) fields.push_back(true);
    auto label = [&](bool image) { return field_image ? (image ? "[image]  " : "[buffer] ") : ""; };
    if ((!only || only == 4000 || fill_only) && cutoff_only.empty()) for (bool image : fields) {
      nlohmann::json j = run_fill_case(device, profiled, quick ? 2000 : 4000, skin > 0 ? skin : FillOptions{}.skin, image);
      j["field"] = image ? "image" : "buffer";
      std::printf("%sfill regime: 0 -> %zu particles in %llu steps, %.2f s: %8.0f steps/s %9.1f us/step, lists rebuilt on %.0f%% of steps  kernels(us/step):",
                  label(image), j["n"].get<size_t>(), static_cast<unsigned long long>(j["steps"].get<uint64_t>()), j["seconds"].get<double>(),
                  j["steps_per_second"].get<double>(), j["us_per_step"].get<double>(), 100 * j["rebuild_share"].get<double>());
      for (const auto& [k, v] : j["kernel_us_per_step"].items()) std::printf(" %s %.1f", k.c_str(), v.get<double>());
      std::printf("%s\n", j["cell_overflow_hits"].get<uint32_t>() ? "  CELL OVERFLOW" : "");
      std::fflush(stdout);
      all["cases"].push_back(j);
    }
    nlohmann::json equal_case;  // the last equal-sphere case: unequal ones print their cost against it
    for (const Case& c : cases) for (bool image : fields) {
      if (fill_only || (only && c.n != only)) continue;
      if (!cutoff_only.empty() && cutoff_only != (c.cutoff_sigma > 0 ? "lj" : "repulsive")) continue;
      nlohmann::json j = run_case(device, profiled, c, quick, image);
      j["field"] = image ? "image" : "buffer";
      if (c.radii_ratio > 1) std::printf("radii 1:%g ", c.radii_ratio);
      std::printf("%sN=%-6zu%s %-10s %10.0f steps/s %12.4g particle-steps/s %9.1f us/step %9.1f cpu-us/step  kernels(us/step):",
                  label(image), c.n, c.births ? "+b" : "  ", j["cutoff"].get<std::string>().c_str(), j["steps_per_second"].get<double>(),
                  j["particle_steps_per_second"].get<double>(), j["us_per_step"].get<double>(),
                  j["cpu_us_per_step"].get<double>());
      for (const auto& [k, v] : j["kernel_us_per_step"].items()) std::printf(" %s %.1f", k.c_str(), v.get<double>());
      std::printf("  rebuilt %.0f%% of steps (update %.1f us then, %.1f otherwise, fastest tenth %.1f)",
                  100 * j["rebuild_share"].get<double>(), j["update_us_rebuild_step"].get<double>(),
                  j["update_us_other_step"].get<double>(), j["update_us_other_step_p10"].get<double>());
      std::printf("%s\n", j["cell_overflow_hits"].get<uint32_t>() ? "  CELL OVERFLOW" : "");
      if (c.radii_ratio == 1) {
        equal_case = j;
      } else if (!equal_case.is_null() && equal_case["n"] == j["n"] && equal_case["cutoff"] == j["cutoff"]) {
        // the cost per particle-step against the equal spheres' line above (same N, packing, cutoff)
        j["cost_vs_equal"] =
            equal_case["particle_steps_per_second"].get<double>() / j["particle_steps_per_second"].get<double>();
        j["cpu_cost_vs_equal"] = j["cpu_us_per_step"].get<double>() / equal_case["cpu_us_per_step"].get<double>();
        std::printf("  radii 1:%g half by number, cost per particle-step / equal spheres': %.2fx wall, %.2fx cpu\n",
                    c.radii_ratio, j["cost_vs_equal"].get<double>(), j["cpu_cost_vs_equal"].get<double>());
      }
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
