// The fill's progress line (FillOptions::progress): phase, particles,
// kinetic energy, rate, time left and peak memory, sent to the caller.
#pragma once
#include <chrono>
#include <cstdint>
#include <functional>

#include "fill/time_left.hpp"
#include "pfill/fill.hpp"

namespace pfill {

class FillReporter {
 public:
  using Callback = std::function<void(const FillProgress&)>;
  explicit FillReporter(Callback callback) : callback_(std::move(callback)) {}

  /// The count expected when full (FillProgress::target) and the schedule
  /// the time-left estimate models.
  void set_schedule(size_t target, const TimeLeftSchedule& schedule);
  TimeLeft& time_left() { return time_left_; }

  /// Enters `phase`; the next report says so.
  void enter(FillPhase phase) { phase_ = phase; }
  FillPhase phase() const { return phase_; }

  /// Reports `particles` at engine step `step` of the fill (`finish_steps`
  /// of them the finish's).
  void report(size_t particles, double kinetic_energy, uint32_t colliding_pairs, uint64_t step,
              uint64_t finish_steps);

  /// Seconds since the fill began.
  double elapsed() const;

 private:
  using Clock = std::chrono::steady_clock;
  Callback callback_;
  FillPhase phase_ = FillPhase::Field;
  size_t target_ = 0;
  Clock::time_point start_ = Clock::now();
  Clock::time_point last_report_ = Clock::now();
  uint64_t last_step_ = 0;
  TimeLeft time_left_{TimeLeftSchedule{}};
};

}  // namespace pfill
