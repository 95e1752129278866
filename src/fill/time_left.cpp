#include "fill/time_left.hpp"

#include <algorithm>
#include <cmath>

namespace pfill {

double TimeLeft::estimate(FillPhase phase, double elapsed, size_t particles, uint64_t step,
                          uint64_t finish_steps) {
  const bool pass1 = phase == FillPhase::Pass1, births = pass1 || phase == FillPhase::Pass2;
  if (!births && phase != FillPhase::Settle && phase != FillPhase::Finish) return -1;
  samples_.push_back({elapsed, particles, step});
  while (samples_.size() > 2 && elapsed - samples_[1].elapsed > 30) samples_.pop_front();
  const double finished = static_cast<double>(finish_steps);
  if (phase == FillPhase::Finish && finished >= kFinishSteps) return -1;
  if (phase == FillPhase::Finish && finished >= 0.1 * kFinishSteps)
    return (kFinishSteps - finished) * (elapsed - finish_start_) / finished;
  // The finish's first steps: its start (a new engine, the particles
  // uploaded and sorted, a round's host work) would pass for slow steps.
  if (phase == FillPhase::Finish && settle_step_ > 0) return (kFinishSteps - finished) * kFinishStepCost * settle_step_;
  const Sample& first = samples_.front();
  if (elapsed - first.elapsed < 2 || step <= first.step || particles == 0) return -1;
  const double n = static_cast<double>(particles);
  const double per_step = (elapsed - first.elapsed) / static_cast<double>(step - first.step);
  const double full = std::max(n, kOverfill * s_.expected);
  if (phase == FillPhase::Settle) settle_step_ = per_step * full / n;
  const double settled = phase == FillPhase::Settle ? static_cast<double>(step - settle_start_) : 0;
  const double settle_left = phase == FillPhase::Finish ? 0 : std::max(0.0, s_.settle_budget - settled);
  const double after = (settle_left + kFinishStepCost * (kFinishSteps - finished)) * per_step * full / n *
                       (births ? kSettleStepCost : 1.0);
  if (!pass1) return after;
  if (particles <= first.particles) return -1;
  const double born = static_cast<double>(particles - first.particles) / static_cast<double>(step - first.step);
  // Waves fill every site's surroundings at once, in about as many steps
  // at every count; past those, or with the report's sites, the births'
  // own fade says.
  const double done = static_cast<double>(step - pass1_start_);
  const double steps_left =
      s_.waves && done < kWavePass1Steps ? kWavePass1Steps - done : pass1_steps_left(born, full - n, n);
  // Steps as the count grows to full cost, on average, as at halfway.
  return steps_left * per_step * 0.5 * (1 + full / n) + after;
}

// Births fade as e^(-s/tau), with tau = gap / births (so the births to come
// add up to the gap), and pass 1 ends when a patience window of W steps
// holds at most the stop share of the particles it ends with, or no birth
// (taken as one). The births in the window ending s steps on are
// births tau e^(-s/tau) (e^(W/tau) - 1); solved for s in logs (no overflow).
double TimeLeft::pass1_steps_left(double births, double gap, double particles) const {
  if (births <= 0) return s_.patience;
  const double w = s_.patience;
  const double tau = std::max(1.0, gap / births);
  const double least = std::max(1.0, s_.stop_share * (particles + gap));  // of the count it ends at
  const double s = tau * (std::log(births * tau / least) + std::log1p(-std::exp(-w / tau))) + w;
  return std::max(0.0, s);
}

}  // namespace pfill
