/// @file stop_tests.hpp
/// @brief The three signals that end pass 1 of a fill ("the object is
/// overfull"), each a small state machine fed one step record at a time.
///
/// 1. KineticEnergyTest (the report's first criterion): an instability is
///    the total kinetic energy rising over `rising_steps` consecutive steps
///    with no birth in between. On each one the fill removes the newest
///    particle, waits `wait_steps` and adds it back; after `max_events`
///    instabilities the object is overfull.
/// 2. CollisionCountTest (the report's second): the number of colliding
///    pairs unchanged and non-zero for `steady_steps` steps. The fill removes
///    one particle and waits; if the count cannot be brought down
///    `max_tries` times in a row, the object is overfull.
/// 3. BlockedSitesTest (pfill's addition, the one a prototype found to end
///    real fills): births keep failing for lack of room at every birth site
///    for `patience` steps.
///
/// The tests only watch; the fill acts on what they return.
#pragma once
#include <cstdint>
#include <algorithm>
#include <string>
#include <vector>

#include "pfill/engine/step_record.hpp"

namespace pfill {

enum class StopCriterion { Blocked, KineticEnergy, Collisions };

/// "blocked", "ke", "collisions" <-> the enum; throws pfill::Error on bad text.
StopCriterion parse_stop_criterion(const std::string& text);
const char* to_string(StopCriterion c);

/// What a test asks of the fill after a step.
enum class StopVerdict {
  Continue,       ///< nothing to do
  RemoveNewest,   ///< an event: take out one particle and wait
  Overfull,       ///< pass 1 is over
};

struct KineticEnergySettings {
  int rising_steps = 20;  ///< consecutive rises that make an instability
  int wait_steps = 200;   ///< steps to wait after removing before re-adding
  int max_events = 3;     ///< instabilities that mean overfull
};

class KineticEnergyTest {
 public:
  explicit KineticEnergyTest(KineticEnergySettings s = {}) : s_(s) {}
  /// `born` says whether a particle was born just before this step.
  StopVerdict observe(const StepRecord& r, bool born);
  int events() const { return events_; }
  /// True while the fill should hold births back (waiting after an event).
  bool waiting() const { return wait_left_ > 0; }
  const KineticEnergySettings& settings() const { return s_; }

 private:
  KineticEnergySettings s_;
  double last_energy_ = -1;
  int rises_ = 0;
  int events_ = 0;
  int wait_left_ = 0;
};

struct CollisionCountSettings {
  int steady_steps = 50;  ///< steps of an unchanged, non-zero count that make an event
  int wait_steps = 200;   ///< steps to wait after a removal before judging again
  int max_tries = 3;      ///< removals in a row that fail to lower the count
};

class CollisionCountTest {
 public:
  explicit CollisionCountTest(CollisionCountSettings s = {}) : s_(s) {}
  StopVerdict observe(const StepRecord& r, bool born);
  int tries() const { return tries_; }
  bool waiting() const { return wait_left_ > 0; }
  const CollisionCountSettings& settings() const { return s_; }

 private:
  CollisionCountSettings s_;
  int64_t last_count_ = -1;
  int steady_ = 0;
  int tries_ = 0;
  int wait_left_ = 0;
  int64_t count_at_event_ = -1;
};

struct BlockedSitesSettings {
  int patience = 1500;  ///< steps without a successful birth at any site
  /// Births in waves over many sites: full also when the births of the
  /// last `patience` steps number at most this share of the particles (a
  /// few sites keep finding room now and then long after the object is
  /// full). 0: only a window without any birth.
  double share = 0;
};

class BlockedSitesTest {
 public:
  explicit BlockedSitesTest(BlockedSitesSettings s = {}) : s_(s), window_(static_cast<size_t>(std::max(1, s.patience)), 0) {}
  /// After each step: whether any site gave birth in it.
  StopVerdict observe(bool any_birth) { return observe(any_birth ? 1 : 0, 0); }
  /// After each step: how many were born in it, and the particle count.
  StopVerdict observe(int births, size_t count);
  int steps_without_birth() const { return idle_; }
  const BlockedSitesSettings& settings() const { return s_; }

 private:
  BlockedSitesSettings s_;
  int idle_ = 0;
  std::vector<int> window_;  ///< births of the last `patience` steps (a ring)
  size_t steps_ = 0;
  long long window_births_ = 0;
};

}  // namespace pfill
