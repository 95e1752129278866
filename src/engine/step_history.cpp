// The per-step records: device ring, partials in flight, read-back (see step_history.hpp).
#include "engine/step_history.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>

namespace pfill {

namespace {

constexpr size_t kRecord = 8;  // floats per history / partial record (common.cl pf_record)

uint32_t as_uint(float f) {
  uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}

}  // namespace

StepHistory::StepHistory(Device& device, size_t capacity, size_t group, Kernel finalize, Run run, cl::Buffer fire,
                         bool minimising)
    : device_(device),
      capacity_(capacity),
      group_(group),
      finalize_(std::move(finalize)),
      run_(std::move(run)),
      fire_(std::move(fire)),
      minimising_(minimising) {
  history_ = device_.make_buffer(capacity_ * kRecord * sizeof(float), "history");
}

void StepHistory::reserve(size_t level1_max, uint64_t steps) {
  finish_pending(steps);
  const size_t g1 = level1_max + 1, g2 = groups(g1) + 1;
  for (auto& b : level1_) b = device_.make_buffer(g1 * kRecord * sizeof(float), "step partials (level 1)");
  for (auto& b : level2_) b = device_.make_buffer(g2 * kRecord * sizeof(float), "step partials (level 2)");
  finalize_.forget_args();  // new buffers may reuse a freed buffer's handle
}

void StepHistory::finish_pending(uint64_t steps) {
  if (level1_pending_ == 0 && level2_pending_ == 0) return;
  const size_t h = capacity_;
  // the last step's level 1 and the level 2 of the one before; scratch: the next step's level-2 output
  finalize_.set_args(level1_prev(steps), cl_uint(level1_pending_), level2_out(steps), level2_prev(steps),
                     cl_uint(level2_pending_), history_, cl_uint((steps + h - 1) % h), cl_uint((steps + h - 2) % h),
                     fire_, cl_uint(steps % 2), cl_uint(steps - 1));
  run_(finalize_, group_);
  level1_pending_ = 0;
  level2_pending_ = 0;
}

void StepHistory::drain(uint64_t steps) {
  finish_pending(steps);
  const size_t count = steps - read_, cap = capacity_;
  if (count == 0) return;
  // Read only the unread slots: one piece, or two when they wrap around.
  std::vector<float>& raw = staging_;
  raw.resize(cap * kRecord);
  const size_t first = read_ % cap, wrapped = std::min(count, cap - first);
  cl::Event ev, ev2;
  check_cl(device_.queue().enqueueReadBuffer(history_, CL_FALSE, first * kRecord * sizeof(float),
                                             wrapped * kRecord * sizeof(float), &raw[first * kRecord], nullptr,
                                             device_.profiled(ev)),
           "clEnqueueReadBuffer", "history");
  device_.note(ev, true);
  if (count > wrapped) {
    check_cl(device_.queue().enqueueReadBuffer(history_, CL_FALSE, 0, (count - wrapped) * kRecord * sizeof(float),
                                               raw.data(), nullptr, device_.profiled(ev2)),
             "clEnqueueReadBuffer", "history");
    device_.note(ev2, true);
  }
  device_.finish();
  for (uint64_t s = read_; s < steps; ++s) {
    const float* r = &raw[(s % cap) * kRecord];
    StepRecord rec;
    rec.step = s;
    rec.kinetic_energy = r[0];
    rec.max_speed = std::sqrt(r[1]);  // the kernels keep squares (common.cl pf_record)
    rec.max_displacement = std::sqrt(r[2]);
    // the fourth sum: the power under FIRE, else the rebuilt flag (common.cl pf_record)
    rec.lists_rebuilt = !minimising_ && r[3] > 0.5f;
    rec.power = minimising_ ? r[3] : 0;
    rec.colliding_pairs = as_uint(r[4]);
    rec.flagged = as_uint(r[5]);
    rec.cell_overflow = as_uint(r[6]);
    rec.particles = as_uint(r[7]);
    backlog_.push_back(rec);
  }
  read_ = steps;
}

std::vector<StepRecord> StepHistory::take() { return std::exchange(backlog_, {}); }

}  // namespace pfill
