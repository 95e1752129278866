// The GPU step form (kernels/gpu_lists.cl, gpu_step.cl): one `advance`
// that rebuilds the lists when due, sums each particle's pair forces in
// fixed point, integrates and meets the wall, ping-pong between two
// copies of the state.
#include <algorithm>
#include <limits>

#include "engine/step_kernels.hpp"

namespace pfill {

namespace {

class GpuStep final : public StepKernels {
 public:
  explicit GpuStep(EngineState& state)
      : StepKernels(state,
                    {"physics.cl", "common.cl", "cells.cl", "gpu_lists.cl", "births_removals.cl", "field.cl",
                     "gpu_step.cl"},
                    shared_defines(state)) {}

 private:
  void enqueue_step(bool force_rebuild) override {
    bind_shared(advance, force_rebuild);
    advance.set("X_out", s.particles.x_next()).set("V_out", s.particles.v_next());
    // an item a particle, and a group for each level-2 partial
    s.run(advance, std::max<size_t>({s.n, s.records->level2_now() * s.choices.work_group, 1}));
  }
  size_t reserve_form(size_t) override { return 0; }
  int copies() const override { return 2; }  // advance reads other particles' X and V
  // one a work-group
  size_t level1_count(size_t count) const override {
    const size_t wg = s.choices.work_group;
    return std::max<size_t>((count + wg - 1) / wg, 1);
  }
  size_t insert_items() const override { return s.n; }
  size_t max_particles() const override { return std::numeric_limits<uint32_t>::max() / 2; }
  const char* form_name() const override { return "GPU"; }
};

}  // namespace

std::unique_ptr<StepKernels> make_gpu_step(EngineState& s) { return std::make_unique<GpuStep>(s); }

}  // namespace pfill
