// The stopping tests of pass 1 (see include/pfill/stop_tests.hpp).
#include "pfill/stop_tests.hpp"

#include "pfill/error.hpp"

namespace pfill {

StopCriterion parse_stop_criterion(const std::string& text) {
  if (text == "blocked") return StopCriterion::Blocked;
  if (text == "ke") return StopCriterion::KineticEnergy;
  if (text == "collisions") return StopCriterion::Collisions;
  throw Error("stop '" + text + "': choose blocked, ke or collisions");
}

const char* to_string(StopCriterion c) {
  switch (c) {
    case StopCriterion::Blocked: return "blocked";
    case StopCriterion::KineticEnergy: return "ke";
    case StopCriterion::Collisions: return "collisions";
  }
  return "?";
}

StopVerdict KineticEnergyTest::observe(const StepRecord& r, bool born) {
  if (wait_left_ > 0) {
    --wait_left_;
    last_energy_ = r.kinetic_energy;
    return StopVerdict::Continue;
  }
  // A birth adds energy by itself: it breaks a run of rises.
  if (born || last_energy_ < 0) rises_ = 0;
  else if (r.kinetic_energy > last_energy_) ++rises_;
  else rises_ = 0;
  last_energy_ = r.kinetic_energy;
  if (rises_ < s_.rising_steps) return StopVerdict::Continue;
  rises_ = 0;
  ++events_;
  if (events_ >= s_.max_events) return StopVerdict::Overfull;
  wait_left_ = s_.wait_steps;
  return StopVerdict::RemoveNewest;
}

StopVerdict CollisionCountTest::observe(const StepRecord& r, bool born) {
  const int64_t count = r.colliding_pairs;
  if (wait_left_ > 0) {
    --wait_left_;
    if (wait_left_ == 0) {
      // Judge the removal: did the count come down?
      if (count < count_at_event_) tries_ = 0;
    }
    last_count_ = count;
    steady_ = 0;
    return StopVerdict::Continue;
  }
  if (born || count == 0 || count != last_count_) steady_ = 0;
  else ++steady_;
  last_count_ = count;
  if (steady_ < s_.steady_steps) return StopVerdict::Continue;
  steady_ = 0;
  ++tries_;
  if (tries_ > s_.max_tries) return StopVerdict::Overfull;
  count_at_event_ = count;
  wait_left_ = s_.wait_steps;
  return StopVerdict::RemoveNewest;
}

StopVerdict BlockedSitesTest::observe(int births, size_t count) {
  idle_ = births > 0 ? 0 : idle_ + 1;
  if (idle_ >= s_.patience) return StopVerdict::Overfull;
  if (s_.share <= 0) return StopVerdict::Continue;
  int& slot = window_[steps_++ % window_.size()];
  window_births_ += births - slot;
  slot = births;
  const bool window_full = steps_ >= window_.size();
  return window_full && static_cast<double>(window_births_) <= s_.share * static_cast<double>(count)
             ? StopVerdict::Overfull
             : StopVerdict::Continue;
}

}  // namespace pfill
