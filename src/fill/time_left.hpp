// The fill's time-left estimate (FillProgress::remaining): a model of the
// passes still to come, timed by the steps just run.
#pragma once
#include <cstddef>
#include <cstdint>
#include <deque>

#include "pfill/fill.hpp"

namespace pfill {

/// What the estimate needs to know of the fill's schedule.
struct TimeLeftSchedule {
  bool waves = false;          ///< births in waves (pass 1 takes about as many steps at every count)
  double expected = 0;         ///< the expected particle count
  double patience = 1500;      ///< pass 1's patience window, in steps
  double stop_share = 0;       ///< pass 1 ends when a window's births are at most this share of the count (0: when none)
  double settle_budget = 2000; ///< most steps of the settle
};

/// Seconds left, from progress samples (phase, seconds since the start,
/// particles, step count), or -1 when there is no honest figure. Pass 1:
/// its steps still to come (with waves, about kWavePass1Steps in all; else
/// from the fade of the births, pass1_steps_left), then the passes after
/// it: what is left of the settle's step budget and kFinishSteps of the
/// finish, each kFinishStepCost settle steps. Steps are timed over the
/// last half minute and scaled to the count they will run at (a step costs
/// about in proportion to the particles). In the finish: its first tenth
/// at the settle's last step cost, then its own steps so far at their
/// average cost, which includes its rounds' host work; past kFinishSteps, -1.
class TimeLeft {
 public:
  explicit TimeLeft(const TimeLeftSchedule& s) : s_(s) {}

  void pass1_started(uint64_t step) { pass1_start_ = step; }
  /// Later steps cost more than pass 1's: timed afresh.
  void pass1_ended() { samples_.clear(); }
  void settle_started(uint64_t step) { settle_start_ = step; }
  void finish_started(double elapsed) { finish_start_ = elapsed; }

  /// `step` counts every step of the fill, the finish's included;
  /// `finish_steps` the finish's alone.
  double estimate(FillPhase phase, double elapsed, size_t particles, uint64_t step, uint64_t finish_steps);

  /// Steps until pass 1 ends, with `births` a step now and `gap` births to
  /// go to the full count, among `particles` (see time_left.cpp).
  double pass1_steps_left(double births, double gap, double particles) const;

  /// Steps of pass 1 with waves (stop share 3%, room sites): spot
  /// 11,520-12,384 at 4,000, 11,472 at 16,000; the bunny 11,952-12,096 at 4,000.
  static constexpr double kWavePass1Steps = 11500;
  /// A settle step costs about this many steps of pass 1 at the same count
  /// (no births, no read-backs of positions; spot at 100,000 and 1e6).
  static constexpr double kSettleStepCost = 0.75;
  /// Steps of the finish in fills of spot: 3,200-9,700 at 4,000, 7,000 at
  /// 16,000, 7,800 at 100,000; it changes when the finish does.
  static constexpr double kFinishSteps = 8000;
  /// A finish step, its rounds' host work included, costs about this many
  /// settle steps (spot: 1.15-1.5 at 4,000, 0.8-1.2 at 100,000 over runs, 1.5 at 1e6).
  static constexpr double kFinishStepCost = 1.3;
  /// Pass 1 ends overfull by about this share of the expected count.
  static constexpr double kOverfill = 1.05;

 private:
  struct Sample {
    double elapsed;
    size_t particles;
    uint64_t step;
  };
  TimeLeftSchedule s_;
  std::deque<Sample> samples_;  ///< the last half minute's
  uint64_t pass1_start_ = 0;
  uint64_t settle_start_ = 0;
  double finish_start_ = 0;
  double settle_step_ = -1;  ///< seconds a settle step took at the full count, last timed
};

}  // namespace pfill
