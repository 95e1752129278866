// bench_variants: two builds of the engine's kernels, with the extra build
// options A and B (PFILL_CL_OPTIONS, e.g. "-DPF_X=0" "-DPF_X=1"), step the
// same system in one process, one step each in turn, every step profiled.
// On a shared machine whose speed swings by 20-30% within minutes, separate
// runs (bench/ab_step.sh) resolve only large effects; steps taken in turn
// meet the same swings, so the two fastest tenths compare within a few %.
// Prints, per variant, the update time of a step (pair_forces + advance,
// profiled) as its median and fastest tenth, over the steps that did not
// rebuild the lists and over all, and the per-kernel medians.
//
//   bench_variants [--n N] [--cutoff lj|repulsive] [--steps S] "OPTIONS_A" "OPTIONS_B"
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "pfill/device/device.hpp"
#include "pfill/engine/engine.hpp"
#include "pfill/error.hpp"

#include "bench_systems.hpp"

using namespace pfill;

namespace {

// The value at fraction q (0: fastest) of the sorted samples.
double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[static_cast<size_t>(q * (v.size() - 1))];
}

struct Variant {
  std::string options;
  std::unique_ptr<Engine> engine;
  std::vector<double> other, all;                     // update seconds: non-rebuild steps, every step
  std::map<std::string, std::vector<double>> kernels;  // seconds a step, per kernel
};

}  // namespace

int main(int argc, char** argv) {
  size_t n = 100000, steps = 300;
  double cutoff = 2.5;
  std::vector<std::string> options;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--n") && i + 1 < argc) n = std::strtoul(argv[++i], nullptr, 10);
    else if (!std::strcmp(argv[i], "--steps") && i + 1 < argc) steps = std::strtoul(argv[++i], nullptr, 10);
    else if (!std::strcmp(argv[i], "--cutoff") && i + 1 < argc) cutoff = std::strcmp(argv[++i], "repulsive") ? 2.5 : 0.0;
    else options.push_back(argv[i]);
  }
  if (options.size() != 2 || n == 0 || steps == 0) {
    std::fprintf(stderr, "usage: bench_variants [--n N] [--cutoff lj|repulsive] [--steps S] \"OPTIONS_A\" \"OPTIONS_B\"\n");
    return 2;
  }
  try {
    Device device("", true);
    std::printf("device: %s; N=%zu, %s, %zu steps each, in turn\n", device.info().name.c_str(), n,
                cutoff > 0 ? "2.5 sigma" : "repulsive", steps);
    std::vector<Particle> ps;
    const double h = bench::fcc_system(n, ps);
    const ScalarGrid field = bench::box_field(h, bench::kRadius / 2);
    EngineParams p = bench::sphere_params(EngineParams{}, false);
    p.cutoff_sigma = cutoff;
    Variant v[2];
    for (int s = 0; s < 2; ++s) {
      v[s].options = options[s];
      // the programs are built in the constructor, with the options of the moment
      setenv("PFILL_CL_OPTIONS", options[s].c_str(), 1);
      v[s].engine = std::make_unique<Engine>(device, p);
      v[s].engine->set_field(field);
      v[s].engine->add_particles(ps);
      v[s].engine->sort_by_cells();
      v[s].engine->run_steps(10);  // warm-up: kernels compiled for this size
      v[s].engine->finish();
      v[s].engine->kernel_times();
      v[s].engine->read_history();
    }
    for (size_t k = 0; k < steps; ++k)
      for (Variant& x : v) {
        x.engine->run_steps(1);
        double update = 0;
        for (const auto& [name, seconds] : x.engine->kernel_times()) {
          x.kernels[name].push_back(seconds);
          if (name == "pair_forces" || name == "advance") update += seconds;
        }
        x.all.push_back(update);
      }
    for (Variant& x : v) {  // each step's record, read once at the end, as a run would
      const std::vector<StepRecord> records = x.engine->read_history();
      for (size_t k = 0; k < x.all.size() && k < records.size(); ++k)
        if (!records[k].lists_rebuilt) x.other.push_back(x.all[k]);
    }
    std::printf("%-32s %16s %16s %16s %16s  kernel medians (us)\n", "options", "other: median", "fastest tenth",
                "all: median", "fastest tenth");
    for (const Variant& x : v) {
      std::printf("%-32s %16.1f %16.1f %16.1f %16.1f ", ('"' + x.options + '"').c_str(), 1e6 * quantile(x.other, 0.5),
                  1e6 * quantile(x.other, 0.1), 1e6 * quantile(x.all, 0.5), 1e6 * quantile(x.all, 0.1));
      for (const auto& [name, t] : x.kernels) std::printf(" %s %.1f", name.c_str(), 1e6 * quantile(t, 0.5));
      std::printf("\n");
    }
    const double a = quantile(v[0].other, 0.1), b = quantile(v[1].other, 0.1);
    std::printf("B / A, fastest tenth of the other steps: %.3f (below 1: B is faster)\n", b / a);
  } catch (const Error& e) {
    std::fprintf(stderr, "bench_variants: %s\n", e.what());
    return 1;
  }
  return 0;
}
