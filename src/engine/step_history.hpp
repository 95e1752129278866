// The per-step records on the device and their way to the host: the
// ring of history records, the partial sums of the steps still in flight
// (level 1 of the last step, level 2 of the one before: kernels/common.cl),
// finishing them (finalize_history), and reading the ring back.
#pragma once
#include <CL/opencl.hpp>

#include <cstdint>
#include <functional>
#include <vector>

#include "pfill/device/device.hpp"
#include "pfill/device/program.hpp"
#include "pfill/engine/step_record.hpp"

namespace pfill {

class StepHistory {
 public:
  /// Runs a kernel over `items` work-items (the engine's launch, which
  /// keeps the profiling events).
  using Run = std::function<void(Kernel&, size_t)>;

  /// `capacity` records on the device; `group` is PF_WG (the chunk of the
  /// level-2 sums); `finalize` the form's finalize_history kernel. `fire`:
  /// the FIRE state's two halves (EngineState::fire), which finalize_history
  /// brings up to date with the records it finishes when `minimising`
  /// (the records' fourth sum is then the power).
  StepHistory(Device& device, size_t capacity, size_t group, Kernel finalize, Run run, cl::Buffer fire,
              bool minimising);

  /// Partial buffers for steps of up to `level1_max` level-1 partials
  /// (finishes the steps in flight first: the buffers are replaced).
  void reserve(size_t level1_max, uint64_t steps);

  /// What step `steps` (0-based) passes to `advance`: its level-1 output,
  /// the last step's level-1 partials and their count, the level-2
  /// output, the level-2 partials of the step before and their count, the
  /// ring, and the slot of that step's record.
  cl::Buffer& level1_out(uint64_t steps) { return level1_[steps % 2]; }
  cl::Buffer& level1_prev(uint64_t steps) { return level1_[1 - steps % 2]; }
  cl_uint level1_pending() const { return static_cast<cl_uint>(level1_pending_); }
  cl::Buffer& level2_out(uint64_t steps) { return level2_[steps % 2]; }
  cl::Buffer& level2_prev(uint64_t steps) { return level2_[1 - steps % 2]; }
  cl_uint level2_pending() const { return static_cast<cl_uint>(level2_pending_); }
  cl::Buffer& ring() { return history_; }
  cl_uint slot_two_back(uint64_t steps) const { return static_cast<cl_uint>((steps + capacity_ - 2) % capacity_); }
  /// The level-2 partials step `steps` makes of the last step's level 1.
  size_t level2_now() const { return groups(level1_pending_); }

  /// After step `steps` was enqueued with `level1` level-1 partials.
  void stepped(size_t level1) {
    level2_pending_ = level2_now();
    level1_pending_ = level1;
  }
  /// Whether step `steps` must first read the ring (it would overwrite an unread record).
  bool full(uint64_t steps) const { return steps - read_ >= capacity_; }

  /// Finishes the reductions of the steps in flight (one work-group).
  void finish_pending(uint64_t steps);
  /// Moves every unread record to the backlog (blocking).
  void drain(uint64_t steps);
  /// The backlog, emptied.
  std::vector<StepRecord> take();

 private:
  size_t groups(size_t count) const { return (count + group_ - 1) / group_; }

  Device& device_;
  size_t capacity_, group_;
  Kernel finalize_;
  Run run_;
  cl::Buffer level1_[2], level2_[2], history_, fire_;
  bool minimising_;
  size_t level1_pending_ = 0;  // >0: level1[(steps - 1) % 2] holds step steps-1's partials, unreduced
  size_t level2_pending_ = 0;  // >0: level2[(steps - 1) % 2] holds step steps-2's partials, unreduced
  uint64_t read_ = 0;          // records read back: steps [0, read_)
  std::vector<StepRecord> backlog_;
  std::vector<float> staging_;  // read-back staging, kept to avoid an allocation per read
};

}  // namespace pfill
