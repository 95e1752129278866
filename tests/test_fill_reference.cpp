// The fill's passes (births, stop tests, removals, settling) on the C++
// reference engine (FillOptions::engine): no OpenCL device is opened, so
// this runs where none exists. The finish needs the OpenCL engine and is
// left out, which the result says.
#include <doctest/doctest.h>

#include <memory>
#include <string>

#include "pfill/engine/reference.hpp"
#include "pfill/fill.hpp"
#include "pfill/shapes.hpp"

using namespace pfill;

TEST_CASE("fill: passes 1-3 run on the reference engine, without an OpenCL device") {
  FillOptions o;
  o.count = 60;
  o.seed = 3;
  o.colour = ColourOptions{ColourMode::None, {}};
  size_t engines = 0;
  o.engine = [&engines](const EngineParams& p) -> std::unique_ptr<ParticleEngine> {
    ++engines;
    return std::make_unique<ReferenceEngine>(p);
  };
  std::string logged;
  o.log = [&logged](const std::string& line) { logged += line; };
  const FillResult r = fill(make_icosphere(1.0, 3), o);
  CHECK(engines == 1);
  CHECK(logged.find("reference engine") != std::string::npos);
  CHECK(r.device.find("none") == 0);
  INFO("particles " << r.metrics.count << ", packing " << r.metrics.packing_fraction << ", stop "
                    << r.stop_reason);
  REQUIRE(r.passes.size() >= 3);
  CHECK(r.passes[0].name == "pass 1");
  CHECK(r.passes[0].steps > 0);
  CHECK(r.passes[2].name == "settle");
  for (const PassStats& p : r.passes) CHECK(p.list_rebuilds == -1);  // (only the OpenCL engine's records say)
  CHECK_FALSE(r.stop_signal.empty());
  // Filled as the OpenCL engine fills (a sphere of 60 expected: well over half of them), contained.
  CHECK(r.particles.size() >= 40);
  CHECK(r.particles.size() <= 90);
  CHECK(r.metrics.packing_fraction > 0.4);
  CHECK(r.metrics.contained_share == 1.0);
  bool said = false;
  for (const std::string& w : r.warnings) said = said || w.find("finish was left out") != std::string::npos;
  CHECK(said);
}
