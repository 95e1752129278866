// The plan's schedule: pass 1's time step, top speed, time between waves
// and patience, automatic by schedule and held in tau when the step changes.
#include <doctest/doctest.h>

#include <cmath>

#include "fill/fill_plan.hpp"
#include "pfill/engine/params.hpp"
#include "pfill/mesh_diagnostics.hpp"
#include "pfill/radius_distribution.hpp"
#include "pfill/shapes.hpp"

using namespace pfill;

namespace {

FillPlan plan_of(const FillOptions& o) {
  const Mesh mesh = make_builtin("sphere");
  return plan_fill(mesh.bounds(), diagnose(mesh), o);
}

FillOptions counted(size_t count) {
  FillOptions o;
  o.count = count;
  return o;
}

/// The top speed in sigma per tau, as the engine derives it.
double top_speed(const FillPlan& plan, const FillOptions& o) {
  const EngineConstants c = derive_constants(plan_engine_params(plan, o));
  return c.max_speed * c.tau / c.sigma;
}

/// The plan's schedule: its step (tau), top step (sigma), wave interval and patience (steps).
void check_schedule(const FillPlan& p, double time_step, double max_step, int birth_every, int patience) {
  CHECK(p.time_step == doctest::Approx(time_step));
  CHECK(p.max_step == doctest::Approx(max_step));
  CHECK(p.birth_every == birth_every);
  CHECK(p.patience == patience);
}

}  // namespace

TEST_CASE("waves of equal spheres step twice the report's step, with the top speed and the times in tau held") {
  const FillOptions waves = counted(4000);
  const FillPlan w = plan_of(waves);
  REQUIRE(w.waves);
  check_schedule(w, 0.02, 0.2, 24, 750);

  // The report's schedule: one site, a birth every step, its own 0.01 tau.
  FillOptions report = counted(4000);
  report.sites = 1;
  report.birth_every = 1;
  const FillPlan r = plan_of(report);
  REQUIRE_FALSE(r.waves);
  check_schedule(r, 0.01, 0.1, 1, 1500);

  // The same top speed, 10 sigma per tau, and the engine's step from the plan's.
  CHECK(top_speed(w, waves) == doctest::Approx(10));
  CHECK(top_speed(r, report) == doctest::Approx(10));
  const EngineConstants cw = derive_constants(plan_engine_params(w, waves));
  CHECK(cw.dt == doctest::Approx(0.02 * cw.tau));
}

TEST_CASE("unequal spheres keep the report's step in waves: 48 steps between waves, 1,500 of patience") {
  FillOptions o = counted(4000);
  o.radii = RadiusDistribution::parse("lognormal:1,0.2");
  const FillPlan p = plan_of(o);
  REQUIRE(p.waves);
  check_schedule(p, 0.01, 0.1, 48, 1500);
}

TEST_CASE("a step given by the caller moves the automatic top speed, waves and patience with it; given ones stand") {
  FillOptions o = counted(4000);
  o.time_step = 0.015;
  FillPlan p = plan_of(o);
  check_schedule(p, 0.015, 0.15, 32, 1000);
  CHECK(top_speed(p, o) == doctest::Approx(10));

  o.max_step = 0.05;
  o.birth_every = 10;
  o.patience = 400;
  p = plan_of(o);
  check_schedule(p, 0.015, 0.05, 10, 400);
  CHECK(top_speed(p, o) == doctest::Approx(0.05 / 0.015));
}
