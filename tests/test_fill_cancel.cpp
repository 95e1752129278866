// FillOptions::cancelled, the hook Ctrl-C reaches a fill through (the
// command line, the Python module): polled at each sync of the passes and
// each read of the finish's relaxations, it stops the fill with pfill::Cancelled.
#include <doctest/doctest.h>

#include <string>

#include "pfill/error.hpp"
#include "pfill/fill.hpp"
#include "pfill/fill_report.hpp"
#include "pfill/shapes.hpp"

using namespace pfill;

TEST_CASE("a fill stops with pfill::Cancelled at the poll that asks it to") {
  FillOptions o;
  o.count = 5000;  // far more steps than the polls below: only a cancel ends it early
  int polls = 0;
  FillPhase phase = FillPhase::Field;
  o.progress = [&](const FillProgress& p) { phase = p.phase; };
  o.cancelled = [&] { return ++polls == 10; };
  CHECK_THROWS_AS(fill(make_builtin("sphere"), o), Cancelled);
  CHECK(polls == 10);
  CHECK(phase == FillPhase::Pass1);
}

TEST_CASE("the finish's relaxations poll the cancel hook too") {
  FillOptions o;
  o.count = 150;
  FillPhase phase = FillPhase::Field;
  int finish_polls = 0;
  o.progress = [&](const FillProgress& p) { phase = p.phase; };
  o.cancelled = [&] { return phase == FillPhase::Finish && ++finish_polls == 2; };
  CHECK_THROWS_AS(fill(make_builtin("cube"), o), Cancelled);
  CHECK(finish_polls == 2);
}

TEST_CASE("a hook that never cancels changes nothing") {
  FillOptions o;
  o.count = 120;
  o.seed = 4;
  const FillResult plain = fill(make_builtin("cube"), o);
  int polls = 0;
  o.cancelled = [&] { return ++polls < 0; };
  const FillResult hooked = fill(make_builtin("cube"), o);
  CHECK(polls > 10);
  REQUIRE(hooked.particles.size() == plain.particles.size());
  CHECK(hooked.metrics.packing_fraction == plain.metrics.packing_fraction);
  // The report (fill_report.hpp) carries the same figures as the metrics.
  const auto report = fill_report_json(hooked, "cube", o.seed, "out.ply");
  CHECK(report["metrics"]["particles"] == hooked.particles.size());
  CHECK(report["seed"] == 4);
  CHECK(report["output"] == "out.ply");
  CHECK(report["metrics"]["packing_fraction"] == hooked.metrics.packing_fraction);
}
