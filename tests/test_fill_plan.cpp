// The plan's schedule: pass 1's time step, top speed, time between waves
// and patience, automatic by schedule and held in tau when the step changes.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "fill/fill_plan.hpp"
#include "pfill/boundary.hpp"
#include "pfill/engine/params.hpp"
#include "pfill/mesh_diagnostics.hpp"
#include "pfill/radius_distribution.hpp"
#include "pfill/sdf.hpp"
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

TEST_CASE("the fill's field is exact at every corner the wall reads: cells holding a centre inside or at the wall") {
  // The wall samples the 8 corners of the cell around a centre; outside the
  // solid its corners lie up to a cell diagonal (1.73 spacings) out, within
  // the plan's outer band, and inside within the band. Corners farther out
  // are interpolated (the band's saving), so a band too thin shows here.
  const Mesh mesh = make_builtin("torus");
  const FillPlan plan = plan_fill(mesh.bounds(), diagnose(mesh), counted(4000));
  const Boundary boundary(mesh);
  const ScalarGrid field = build_signed_distance_field(boundary, plan.field);
  SdfOptions all = plan.field;
  all.band = all.outer_band = std::numeric_limits<double>::infinity();
  const ScalarGrid exact = build_signed_distance_field(boundary, all);
  REQUIRE(field.dims == exact.dims);
  const double h = field.spacing, reach = plan.radius + 2 * h;  // (the wall acts within r of it)
  size_t cells = 0, interpolated = 0;
  for (int k = 0; k + 1 < field.dims[2]; ++k)
    for (int j = 0; j + 1 < field.dims[1]; ++j)
      for (int i = 0; i + 1 < field.dims[0]; ++i) {
        // A cell some centre inside can lie in: one corner inside, all within reach of the wall.
        bool inside = false, near = true;
        for (int n = 0; n < 8; ++n) {
          const float v = exact.at(i + (n & 1), j + (n >> 1 & 1), k + (n >> 2));
          inside = inside || v <= 0;
          near = near && std::fabs(v) < reach;
        }
        if (!inside || !near) continue;
        ++cells;
        for (int n = 0; n < 8; ++n) {
          const int a = i + (n & 1), b = j + (n >> 1 & 1), c = k + (n >> 2);
          if (field.at(a, b, c) != exact.at(a, b, c)) ++interpolated;
        }
      }
  CHECK(cells > 1000);
  CHECK(interpolated == 0);
  // ... and the band did save queries: some sample farther out is not exact.
  size_t differ = 0;
  for (size_t n = 0; n < field.size(); ++n) differ += field.values[n] != exact.values[n];
  CHECK(differ > 0);
}
