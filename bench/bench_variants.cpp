// bench_variants: two builds of the engine's kernels, with the extra build
// options A and B (PFILL_CL_OPTIONS, e.g. "-DPF_X=0" "-DPF_X=1"), step the
// same system in one process, one step each in turn, every step profiled.
// On a shared machine whose speed swings by 20-30% within minutes, separate
// runs (bench/ab_step.sh) resolve only large effects; steps taken in turn
// meet the same swings, so the two fastest tenths compare within a few %.
// A variant's words of the form name=value set EngineParams instead:
// skin, inner_skin (sigma), inner_lists, pair_queue, newton (on, off);
// kernels=DIR builds that variant from the kernel files in DIR
// (PFILL_KERNEL_DIR), e.g. another revision's:
//   mkdir /tmp/old && for f in kernels/*.cl; do git show HEAD:$f > /tmp/old/${f#kernels/}; done
//   then bench_variants "kernels=/tmp/old" "" (a revision with the same
//   kernel files and arguments as this build's host code)
// Prints, per variant, the update time of a step (pair_forces + advance,
// profiled) as its median and fastest tenth over the steps that did not
// rebuild the lists, its median over those that did (and their number), (whose fastest tenth is the steadiest figure for the
// pair loop) and over all steps (whose mean, pruning and rebuild steps
// included, is what a run's rate follows), and the per-kernel medians;
// with --quantiles also the quantiles of all steps (the rebuild and the
// pruning steps show as the slow tail).
//
//   bench_variants [--n N] [--cutoff lj|repulsive] [--steps S] [--quantiles] "OPTIONS_A" "OPTIONS_B"
//   e.g. bench_variants "inner_skin=0.1" "inner_skin=0.15"
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <sstream>
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

// The build options of a variant, with its name=value words applied to `p`
// (kernels=DIR to `kernel_dir`).
std::string apply_words(const std::string& spec, EngineParams& p, std::string& kernel_dir) {
  std::istringstream in(spec);
  std::string word, options;
  while (in >> word) {
    const size_t eq = word.find('=');
    if (word[0] == '-' || eq == std::string::npos) {
      options += (options.empty() ? "" : " ") + word;
      continue;
    }
    const std::string name = word.substr(0, eq), value = word.substr(eq + 1);
    if (name == "kernels") kernel_dir = value;
    else if (name == "skin") p.skin_sigma = std::stod(value);
    else if (name == "inner_skin") p.inner_skin_sigma = std::stod(value);
    else if (name == "inner_lists") p.inner_lists = value == "on" ? InnerLists::on : InnerLists::off;
    else if (name == "pair_queue") p.pair_queue = value == "on" ? PairQueue::on : PairQueue::off;
    else if (name == "newton") p.newton = value == "on" ? Newton::on : Newton::off;
    else throw Error("bench_variants: unknown setting '" + name + "'");
  }
  return options;
}

double mean(const std::vector<double>& v) {
  double sum = 0;
  for (double x : v) sum += x;
  return v.empty() ? 0 : sum / v.size();
}

struct Variant {
  std::string options;
  std::unique_ptr<Engine> engine;
  std::vector<double> other, rebuild, all;            // update seconds: non-rebuild steps, rebuild steps, every step
  std::map<std::string, std::vector<double>> kernels;  // seconds a step, per kernel
};

}  // namespace

int main(int argc, char** argv) {
  size_t n = 100000, steps = 300;
  double cutoff = 2.5;
  bool quantiles = false;
  std::vector<std::string> options;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--n") && i + 1 < argc) n = std::strtoul(argv[++i], nullptr, 10);
    else if (!std::strcmp(argv[i], "--steps") && i + 1 < argc) steps = std::strtoul(argv[++i], nullptr, 10);
    else if (!std::strcmp(argv[i], "--quantiles")) quantiles = true;
    else if (!std::strcmp(argv[i], "--cutoff") && i + 1 < argc) cutoff = std::strcmp(argv[++i], "repulsive") ? 2.5 : 0.0;
    else options.push_back(argv[i]);
  }
  if (options.size() != 2 || n == 0 || steps == 0) {
    std::fprintf(stderr, "usage: bench_variants [--n N] [--cutoff lj|repulsive] [--steps S] [--quantiles] \"OPTIONS_A\" \"OPTIONS_B\"\n");
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
      EngineParams ps_params = p;
      std::string kernel_dir;
      const std::string build = apply_words(options[s], ps_params, kernel_dir);
      // the programs are built in the constructor, with the options of the moment
      setenv("PFILL_CL_OPTIONS", build.c_str(), 1);
      setenv("PFILL_KERNEL_DIR", kernel_dir.c_str(), 1);
      v[s].engine = std::make_unique<Engine>(device, ps_params);
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
        (records[k].lists_rebuilt ? x.rebuild : x.other).push_back(x.all[k]);
    }
    std::printf("%-32s %14s %14s %16s %14s %14s  kernel medians (us)\n", "variant", "other: median", "fastest tenth",
                "rebuilds: median", "all: median", "mean");
    for (const Variant& x : v) {
      std::printf("%-32s %14.1f %14.1f %10.1f (%3zu) %14.1f %14.1f ", ('"' + x.options + '"').c_str(),
                  1e6 * quantile(x.other, 0.5), 1e6 * quantile(x.other, 0.1), 1e6 * quantile(x.rebuild, 0.5),
                  x.rebuild.size(), 1e6 * quantile(x.all, 0.5), 1e6 * mean(x.all));
      for (const auto& [name, t] : x.kernels) std::printf(" %s %.1f", name.c_str(), 1e6 * quantile(t, 0.5));
      std::printf("\n");
      if (quantiles) {
        std::printf("%32s", "all steps' quantiles (us):");
        for (double q : {0.1, 0.3, 0.5, 0.7, 0.8, 0.9, 0.95, 0.97, 0.99}) std::printf(" p%.0f %.0f", 100 * q, 1e6 * quantile(x.all, q));
        std::printf("\n");
      }
    }
    std::printf("B / A: fastest tenth of the other steps %.3f, mean of all steps %.3f (below 1: B is faster)\n",
                quantile(v[1].other, 0.1) / quantile(v[0].other, 0.1), mean(v[1].all) / mean(v[0].all));
  } catch (const Error& e) {
    std::fprintf(stderr, "bench_variants: %s\n", e.what());
    return 1;
  }
  return 0;
}
