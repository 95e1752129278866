// The CPU step form (kernels/cpu_pairs.cl, cpu_step.cl; ARCHITECTURE.md
// "The step on CPUs and GPUs"): pair_forces into per-core force buffers,
// then `advance` in place, an octet of particles a work-item.
#include <algorithm>

#include "engine/step_kernels.hpp"

namespace pfill {

namespace {

class CpuStep final : public StepKernels {
 public:
  explicit CpuStep(EngineState& state)
      : StepKernels(state,
                    {"physics.cl", "common.cl", "x86.cl", "cells.cl", "cpu_lists.cl", "births_removals.cl", "field.cl",
                     "cpu_pairs.cl", "cpu_step.cl"},
                    shared_defines(state)),
        forces_(state.device, "pair forces"),
        build_bits_(state.device, "list build bits"),
        force_spans_(state.device, "pair force spans") {
    pairs_ = program.kernel("pair_forces", 1);
  }

 private:
  void enqueue_step(bool force_rebuild) override {
    const cl_uint stride = cl_uint(s.particles.capacity());
    bind_shared(pairs_, force_rebuild);
    pairs_.set("build_bits", build_bits_).set("F", forces_).set("force_stride", stride);
    pairs_.set("force_spans", force_spans_);
    // with Newton one work-item per force buffer, else one per 64 particles
    s.run(pairs_, s.choices.newton ? force_groups_ : std::max<size_t>(1, (s.n + 63) / 64));
    bind_shared(advance, force_rebuild);
    advance.set("F", forces_).set("force_groups", cl_uint(force_groups_)).set("force_stride", stride);
    advance.set("force_spans", force_spans_).set("build_bits", build_bits_);
    // an item an octet, and a group for each level-2 partial
    s.run(advance, std::max<size_t>({level1_count(s.n), s.records->level2_now() * s.choices.work_group, 1}));
  }

  size_t reserve_form(size_t cap) override {
    force_groups_ = force_buffers(cap);
    forces_.reset(force_groups_ * cap, true);  // zero between steps
    build_bits_.reset(cap);
    force_spans_.reset(force_groups_, true);
    return force_groups_;
  }

  // With Newton EngineParams::force_buffers, or one per compute unit
  // within 512 MiB; else 1.
  size_t force_buffers(size_t cap) const {
    if (!s.choices.newton) return 1;
    if (s.params.force_buffers > 0) return s.params.force_buffers;
    const size_t by_memory = (size_t(512) << 20) / (cap * sizeof(cl_float4));
    return std::clamp<size_t>(std::min<size_t>(s.device.info().compute_units, by_memory), 1, 16);
  }

  int copies() const override { return 1; }  // in place: advance reads only its own particle
  // one an octet of particles, the last maybe partial
  size_t level1_count(size_t count) const override { return std::max<size_t>((count + 7) / 8, 1); }
  // a group a core, each item looping (a launch of n items costs PoCL ~0.2 us a group even on the
  // steps that return at once)
  size_t insert_items() const override {
    return std::min(s.n, std::max<size_t>(1, s.device.info().compute_units) * s.params.work_group);
  }
  // List rows hold byte offsets (16 j: PF_ENTRY in cpu_lists.cl), which the
  // AVX-512 gathers take as signed 32-bit.
  size_t max_particles() const override { return size_t(1) << 27; }
  const char* form_name() const override { return "CPU"; }
  std::vector<Kernel*> kernels() override {
    std::vector<Kernel*> all = StepKernels::kernels();
    all.push_back(&pairs_);
    return all;
  }

  Kernel pairs_;
  size_t force_groups_ = 1;  // force buffers `advance` adds up (one per pair_forces work-item with Newton)
  DeviceArray<cl_float4> forces_;   // force_groups_ x capacity forces
  DeviceArray<cl_uint> build_bits_;  // the list build's overflow bits for `advance`
  DeviceArray<cl_uint2> force_spans_;  // with Newton, per force buffer: the particles [first, end) it changed
};

}  // namespace

std::unique_ptr<StepKernels> make_cpu_step(EngineState& s) { return std::make_unique<CpuStep>(s); }

}  // namespace pfill
