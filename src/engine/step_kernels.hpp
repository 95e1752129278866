// A step form's program and kernels (kernels/*.cl by role): the kernels
// both forms share (cells, births, removals), bound to the engine's parts
// by their parameters' names, and the form's own step, which CpuStep
// (cpu_step.cpp) and GpuStep (gpu_step.cpp) write.
#pragma once
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "engine/engine_state.hpp"

namespace pfill {

class StepKernels {
 public:
  /// The form `s.choices` names, built for `s`'s device.
  static std::unique_ptr<StepKernels> make(EngineState& s);
  virtual ~StepKernels() = default;

  /// One step: the cells (only when the lists will be rebuilt), the form's
  /// kernels, the records' bookkeeping.
  void step();
  /// Room for `cap` particles in every part (state kept; doubling is the caller's).
  void reserve(size_t cap);
  /// The grid over `box` (the lists are then rebuilt); with the wall's
  /// field, slots only where spheres can be (CellGrid::set_domain).
  void set_domain(const Box3& box, const ScalarGrid* field = nullptr);

  /// Births and removals (births_removals.cl): one particle written, one
  /// linked into the lists in place, one removed from them (the last
  /// particle renamed to `gone`), one moved to another index.
  void birth(size_t index, const cl_float4& x, const cl_float4& v);
  void birth_linked(const cl_float4& x, const cl_float4& v);
  void remove_linked(size_t gone);
  void move(size_t from, size_t to);
  /// For tests: each particle's neighbours from the cells (blocking).
  std::vector<std::vector<uint32_t>> neighbour_lists();

 protected:
  StepKernels(EngineState& s, const std::vector<std::string>& files, std::map<std::string, std::string> defines);

  /// The form's step after insert_cells: `rebuild` when the lists are due.
  virtual void enqueue_step(bool rebuild) = 0;
  /// The form's own buffers for `cap` particles; returns how many
  /// pair_forces blocks (force buffers) the lists are packed for.
  virtual size_t reserve_form(size_t cap) = 0;
  /// Copies of X and V (2: ping-pong); level-1 partials of a step of `count`.
  virtual int copies() const = 0;
  virtual size_t level1_count(size_t count) const = 0;
  /// Work-items of insert_cells for the current particles.
  virtual size_t insert_items() const = 0;
  /// The most particles the form holds, and its name for errors.
  virtual size_t max_particles() const = 0;
  virtual const char* form_name() const = 0;
  /// Every kernel of the form (their arguments are forgotten when buffers change).
  virtual std::vector<Kernel*> kernels();

  /// Sets each of the engine's shared arguments that `k` declares (the
  /// particles, the cells, the lists, the request words, the wall, the
  /// records) for step s.steps; `rebuild`: the lists are due.
  void bind_shared(Kernel& k, bool rebuild);
  void insert_cells(bool force);

  EngineState& s;
  Program program;
  Kernel advance, insert, birth_one, move_particle, link_birth, unlink_removal, list_neighbours;
};

/// The defines every program of the engine's shares (kernels/common.cl).
std::map<std::string, std::string> shared_defines(const EngineState& s);

}  // namespace pfill
