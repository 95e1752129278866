// The progress line's time-left estimate (fill/time_left.hpp): pass 1's end
// against a simulated birth fade run through the real stop test, each
// later phase's arithmetic on steps of known cost, and a fill's progress
// reports through its finish.
#include <doctest/doctest.h>

#include <cmath>

#include "fill/time_left.hpp"
#include "pfill/fill.hpp"
#include "pfill/shapes.hpp"
#include "pfill/stop_tests.hpp"

using namespace pfill;

namespace {

/// A pass 1 whose births fade as b0 e^(-s/tau) (whole births, the
/// fractions carried), ended by BlockedSitesTest: the step it ends at.
struct FadingBirths {
  double b0, tau;
  double carried = 0;
  size_t n;
  explicit FadingBirths(double b, double t, size_t n0) : b0(b), tau(t), n(n0) {}
  int births_at(uint64_t s) {
    carried += b0 * std::exp(-static_cast<double>(s) / tau);
    const int whole = static_cast<int>(carried);
    carried -= whole;
    n += static_cast<size_t>(whole);
    return whole;
  }
};

uint64_t end_of_pass1(double b0, double tau, size_t n0, const BlockedSitesSettings& stop) {
  FadingBirths f(b0, tau, n0);
  BlockedSitesTest test(stop);
  for (uint64_t s = 0;; ++s)
    if (test.observe(f.births_at(s), f.n) == StopVerdict::Overfull) return s + 1;
}

TimeLeftSchedule schedule(bool waves, double expected, double share) {
  TimeLeftSchedule s;
  s.waves = waves;
  s.expected = expected;
  s.patience = 1500;
  s.stop_share = share;
  s.settle_budget = 2000;
  return s;
}

}  // namespace

TEST_CASE("pass 1's steps left agree with a simulated fade ended by the real stop test") {
  for (const double share : {0.01, 0.003, 0.0}) {
    const double b0 = 20, tau = 2000;
    const size_t n0 = 1000;
    const BlockedSitesSettings stop{1500, share};
    const uint64_t end = end_of_pass1(b0, tau, n0, stop);
    const double full = static_cast<double>(n0) + b0 * tau;  // all births ever
    TimeLeft t(schedule(false, full / TimeLeft::kOverfill, share));
    for (const uint64_t at : {1000, 3000, 6000}) {
      if (at >= end) continue;
      FadingBirths f(b0, tau, n0);
      for (uint64_t s = 0; s < at; ++s) f.births_at(s);
      const double births = b0 * std::exp(-static_cast<double>(at) / tau);
      const double left = t.pass1_steps_left(births, full - static_cast<double>(f.n), static_cast<double>(f.n));
      INFO("share " << share << ", at step " << at << ", pass 1 ends at " << end << ", estimated " << at + left);
      CHECK(left == doctest::Approx(static_cast<double>(end - at)).epsilon(0.1));
    }
  }
}

TEST_CASE("no births now: pass 1 ends within its patience window") {
  TimeLeft t(schedule(false, 1000, 0.01));
  CHECK(t.pass1_steps_left(0, 500, 1000) == 1500);
}

TEST_CASE("phases without a model give no figure") {
  TimeLeft t(schedule(true, 1000, 0.01));
  for (FillPhase phase : {FillPhase::Field, FillPhase::Verify}) CHECK(t.estimate(phase, 10, 1000, 100, 0) == -1);
}

TEST_CASE("the settle: its budget left, then the finish's steps, at the step's cost now") {
  const double expected = 1000, per_step = 0.01;
  TimeLeft t(schedule(true, expected, 0.01));
  const size_t n = 1050;  // pass 1's overfull count: no scaling up to it
  t.settle_started(20000);
  CHECK(t.estimate(FillPhase::Settle, 100, n, 20000, 0) == -1);  // no timing yet
  const double at_500 = t.estimate(FillPhase::Settle, 100 + 500 * per_step, n, 20500, 0);
  CHECK(at_500 == doctest::Approx((1500 + TimeLeft::kFinishStepCost * TimeLeft::kFinishSteps) * per_step));
  const double at_1500 = t.estimate(FillPhase::Settle, 100 + 1500 * per_step, n, 21500, 0);
  CHECK(at_500 - at_1500 == doctest::Approx(1000 * per_step));
}

TEST_CASE("the finish: its steps so far at their average cost, then no figure past the expected steps") {
  TimeLeft t(schedule(true, 1000, 0.01));
  t.finish_started(50);
  const uint64_t before = 22000;
  // 3,000 steps in 45 s (host work between relaxations included): 15 ms a step.
  CHECK(t.estimate(FillPhase::Finish, 95, 1000, before + 3000, 3000) ==
        doctest::Approx((TimeLeft::kFinishSteps - 3000) * 0.015));
  CHECK(t.estimate(FillPhase::Finish, 200, 1000, before + 10000, 10000) == -1);
}

TEST_CASE("the finish's first steps are timed by the settle's, not by the finish's start-up") {
  TimeLeft t(schedule(true, 1000, 0.01));
  const size_t n = 1050;
  t.settle_started(20000);
  t.estimate(FillPhase::Settle, 100, n, 20000, 0);
  t.estimate(FillPhase::Settle, 110, n, 21000, 0);  // 10 ms a step
  t.finish_started(111);
  // 100 steps of the finish after 30 s of its start-up (engine, upload, sort).
  CHECK(t.estimate(FillPhase::Finish, 141, n, 21100, 100) ==
        doctest::Approx((TimeLeft::kFinishSteps - 100) * TimeLeft::kFinishStepCost * 0.01));
}

TEST_CASE("pass 1 with waves: the steps left count down to the waves' usual total, then follow the births") {
  const double expected = 10000, per_step = 0.002;
  TimeLeft t(schedule(true, expected, 0.01));
  t.pass1_started(0);
  const size_t n = static_cast<size_t>(TimeLeft::kOverfill * expected);  // as full as it gets: no scaling up
  auto at = [&](uint64_t step, size_t count) { return t.estimate(FillPhase::Pass1, per_step * step, count, step, 0); };
  at(4000, n - 1);
  const double early = at(6000, n);
  TimeLeft later(schedule(true, expected, 0.01));
  later.pass1_started(0);
  const auto last = static_cast<uint64_t>(TimeLeft::kWavePass1Steps) - 1000;  // still within the waves' usual steps
  later.estimate(FillPhase::Pass1, per_step * static_cast<double>(last - 2000), n - 1, last - 2000, 0);
  const double late = later.estimate(FillPhase::Pass1, per_step * static_cast<double>(last), n, last, 0);
  const double after = (2000 + TimeLeft::kFinishStepCost * TimeLeft::kFinishSteps) * TimeLeft::kSettleStepCost * per_step;
  // The count is full either way, so a step costs the same.
  CHECK(early - after == doctest::Approx((TimeLeft::kWavePass1Steps - 6000) * per_step).epsilon(0.01));
  CHECK(early - late == doctest::Approx((static_cast<double>(last) - 6000) * per_step).epsilon(0.01));
  // Past the waves' usual steps the births' fade decides: 2 births in
  // 2,000 steps, far under the stop share: a patience window or less.
  TimeLeft past(schedule(true, expected, 0.01));
  past.pass1_started(0);
  past.estimate(FillPhase::Pass1, per_step * 18000, n - 2, 18000, 0);
  const double over = past.estimate(FillPhase::Pass1, per_step * 20000, n, 20000, 0) - after;
  CHECK(over > 0);
  CHECK(over <= 1500 * per_step * 1.01);
}

TEST_CASE("a fill reports progress through its finish, at every read of the relaxations") {
  FillOptions o;
  o.count = 300;
  o.colour = ColourOptions{ColourMode::None, {}};
  uint64_t finish_reports = 0, last_step = 0;
  bool steps_rise = true;
  o.progress = [&](const FillProgress& p) {
    if (p.phase != FillPhase::Finish) return;
    ++finish_reports;
    steps_rise = steps_rise && p.step >= last_step;
    last_step = p.step;
  };
  const FillResult r = fill(make_builtin("cube"), o);
  REQUIRE(r.passes.size() == 4);
  CHECK(r.passes[3].name == "finish");
  // A read every 100 steps (FinishSettings::chunk_steps), and the phase's first report.
  CHECK(finish_reports >= r.passes[3].steps / 100 + 1);
  CHECK(steps_rise);
  CHECK(last_step == r.steps);
}
