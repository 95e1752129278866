// Shared by the engine and physics tests: analytic signed distance grids
// (sphere, box) and random particle systems with fixed seeds.
#pragma once
#include "pfill/device/device.hpp"
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <string>
#include <random>
#include <vector>

#include "pfill/engine/engine.hpp"
#include "pfill/grid.hpp"

namespace pfill::test {

// The step forms and the CPU form's variants, for tests that compare each
// with the double reference.
struct StepFormCase {
  const char* name;
  StepForm form;
  Newton newton;
  PairQueue queue;
  InnerLists inner;

  /// `p` set to step in this form.
  EngineParams& apply(EngineParams& p) const {
    p.step_form = form;
    p.newton = newton;
    p.pair_queue = queue;
    p.inner_lists = inner;
    return p;
  }
};
inline const StepFormCase kStepForms[] = {
    {"gpu", StepForm::gpu, Newton::automatic, PairQueue::automatic, InnerLists::automatic},
    {"cpu newton queue", StepForm::cpu, Newton::on, PairQueue::on, InnerLists::off},
    {"cpu newton rows", StepForm::cpu, Newton::on, PairQueue::off, InnerLists::off},
    {"cpu newton inner", StepForm::cpu, Newton::on, PairQueue::off, InnerLists::on},
    {"cpu twice queue", StepForm::cpu, Newton::off, PairQueue::on, InnerLists::off},
    {"cpu twice inner", StepForm::cpu, Newton::off, PairQueue::off, InnerLists::on},
};

// Exact signed distance of a sphere (centre 0, radius R) and of a box (centre 0, half-extents h).
inline double sphere_distance(const Vec3& p, double R) { return length(p) - R; }
inline double box_distance(const Vec3& p, const Vec3& h) {
  const Vec3 q{std::fabs(p.x) - h.x, std::fabs(p.y) - h.y, std::fabs(p.z) - h.z};
  const Vec3 outside{std::max(q.x, 0.0), std::max(q.y, 0.0), std::max(q.z, 0.0)};
  return length(outside) + std::min(std::max(q.x, std::max(q.y, q.z)), 0.0);
}

inline ScalarGrid sphere_grid(double R, double spacing) {
  return sampled_grid(R, spacing, [R](const Vec3& p) { return sphere_distance(p, R); });
}
inline ScalarGrid box_grid(const Vec3& h, double spacing) {
  const double e = std::max(h.x, std::max(h.y, h.z));
  return sampled_grid(e, spacing, [h](const Vec3& p) { return box_distance(p, h); });
}

// n particles of radius r, centres inside `inside(p) <= -r`, pairwise at
// least min_gap * 2r apart (rejection sampling), velocities uniform in
// [-speed, speed]^3. Deterministic for a seed.
template <typename Inside>
std::vector<Particle> random_particles(size_t n, double r, double bound, double min_gap, double speed, unsigned seed,
                                       Inside inside) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> pos(-bound, bound), vel(-speed, speed);
  std::vector<Particle> out;
  size_t tries = 0;
  while (out.size() < n && tries++ < 1000000) {
    const Vec3 p{pos(rng), pos(rng), pos(rng)};
    if (inside(p) > -r) continue;
    bool ok = true;
    for (const Particle& q : out)
      if (length(q.position - p) < min_gap * 2 * r) { ok = false; break; }
    if (!ok) continue;
    Particle part;
    part.position = p;
    part.velocity = {vel(rng), vel(rng), vel(rng)};
    part.radius = r;
    out.push_back(part);
  }
  return out;
}

inline Vec3 total_momentum(const std::vector<Particle>& ps) {
  Vec3 m;
  for (const Particle& p : ps) m += p.mass * p.velocity;
  return m;
}

/// One device for all the tests of an executable (PFILL_DEVICE picks it):
/// opening a device and building kernels once keeps the suite fast.
inline Device& shared_device() {
  static Device device;
  return device;
}

/// Engine settings for a test: the defaults, with the step form that
/// PFILL_TEST_STEP_FORM names (cpu or gpu; unset: the device's own), and
/// the CPU form's settings PFILL_TEST_NEWTON, PFILL_TEST_PAIR_QUEUE,
/// PFILL_TEST_INNER_LISTS (on, off) and PFILL_TEST_FORCE_BUFFERS. ctest runs the engine tests once more
/// with each, so CI checks all of that code.
inline EngineParams test_params() {
  EngineParams p;
  if (const char* form = std::getenv("PFILL_TEST_STEP_FORM"))
    p.step_form = std::string(form) == "gpu" ? StepForm::gpu : StepForm::cpu;
  if (const char* buffers = std::getenv("PFILL_TEST_FORCE_BUFFERS")) p.force_buffers = std::stoul(buffers);
  if (const char* newton = std::getenv("PFILL_TEST_NEWTON"))
    p.newton = std::string(newton) == "off" ? Newton::off : Newton::on;
  if (const char* queue = std::getenv("PFILL_TEST_PAIR_QUEUE"))
    p.pair_queue = std::string(queue) == "off" ? PairQueue::off : PairQueue::on;
  if (const char* inner = std::getenv("PFILL_TEST_INNER_LISTS"))
    p.inner_lists = std::string(inner) == "off" ? InnerLists::off : InnerLists::on;
  return p;
}

/// An engine's neighbour lists (`got`, any order within a list) against
/// the reference's (`want`): how many lists differ, and how many pairs
/// `want` lists (so a test can tell that the lists are not trivially empty).
struct ListsCompared {
  size_t differ = 0, pairs = 0;
};
inline ListsCompared compare_lists(std::vector<std::vector<uint32_t>> got, std::vector<std::vector<uint32_t>> want) {
  ListsCompared out;
  out.differ = got.size() == want.size() ? 0 : 1 + std::max(got.size(), want.size());
  for (size_t i = 0; i < std::min(got.size(), want.size()); ++i) {
    std::sort(got[i].begin(), got[i].end());
    std::sort(want[i].begin(), want[i].end());
    out.differ += got[i] == want[i] ? 0 : 1;
    out.pairs += want[i].size();
  }
  return out;
}

/// PFILL_CL_OPTIONS set to `options` while this lives (programs take the
/// options of the moment: e.g. a kernel variant's -D), then as it was.
class ScopedClOptions {
 public:
  explicit ScopedClOptions(const std::string& options) {
    if (const char* was = std::getenv("PFILL_CL_OPTIONS")) before_ = was;
    setenv("PFILL_CL_OPTIONS", options.c_str(), 1);
  }
  ~ScopedClOptions() {
    if (before_)
      setenv("PFILL_CL_OPTIONS", before_->c_str(), 1);
    else
      unsetenv("PFILL_CL_OPTIONS");
  }
  ScopedClOptions(const ScopedClOptions&) = delete;
  ScopedClOptions& operator=(const ScopedClOptions&) = delete;

 private:
  std::optional<std::string> before_;
};

}  // namespace pfill::test
