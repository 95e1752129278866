// Particle ids through a fill: each particle keeps its id through the
// engine's removals and renumberings along the cells, the relief and the
// final checks, so a particle can be followed from frame to frame.
#include <doctest/doctest.h>

#include <map>
#include <set>

#include "engine_fixtures.hpp"
#include "pfill/device/device.hpp"
#include "pfill/engine/engine.hpp"
#include "pfill/fill.hpp"
#include "pfill/shapes.hpp"

using namespace pfill;

TEST_CASE("a fill's ids are unique, stable across frames and in the result; the result has velocities") {
  FillOptions o;
  o.count = 250;
  o.seed = 3;
  o.sort_every = 64;  // renumber often: ids must follow the particles
  o.colour = ColourOptions{ColourMode::None, {}};
  o.frame_every = 10;
  o.sync_every = 10;  // a frame can come only at the end of a batch of steps
  o.max_step = 0.1;   // the top speed the reach below counts with
  std::vector<ParticleSet> frames;
  std::vector<uint64_t> steps;
  o.on_frame = [&](uint64_t step, const ParticleSet& s) { frames.push_back(s), steps.push_back(step); };
  const FillResult r = fill(make_builtin("sphere"), o);

  REQUIRE(frames.size() >= 20);
  REQUIRE(r.particles.ids.size() == r.particles.size());
  REQUIRE(r.particles.velocities.size() == r.particles.size());
  const std::set<uint64_t> final_ids(r.particles.ids.begin(), r.particles.ids.end());
  CHECK(final_ids.size() == r.particles.size());
  CHECK(*final_ids.begin() >= 1);

  // Between two frames k steps apart a particle moves at most k top-speed
  // steps (max_step_fraction sigma each, sigma < 2r): 2r for k = 10. A
  // wrong id after a renumbering would point at a particle elsewhere.
  size_t followed = 0;
  for (size_t f = 0; f + 1 < frames.size(); ++f) {
    const double reach = double(steps[f + 1] - steps[f]) * o.max_step * 2 * r.radius * 1.01;
    INFO("frames at steps " << steps[f] << " and " << steps[f + 1]);
    std::map<uint64_t, Vec3> before;
    for (size_t i = 0; i < frames[f].size(); ++i) before[frames[f].ids.at(i)] = frames[f].positions[i];
    CHECK(before.size() == frames[f].size());  // unique within a frame
    for (size_t i = 0; i < frames[f + 1].size(); ++i) {
      const auto it = before.find(frames[f + 1].ids.at(i));
      if (it == before.end()) continue;  // born since
      ++followed;
      CHECK(length(frames[f + 1].positions[i] - it->second) <= reach);
    }
  }
  CHECK(followed > 500);

  // The velocities are the engine's, not zeros (--velocities wrote none before).
  double fastest = 0;
  for (const Vec3& v : frames[frames.size() / 2].velocities) fastest = std::max(fastest, length(v));
  CHECK(fastest > 0);
  REQUIRE(frames[0].velocities.size() == frames[0].size());
}

TEST_CASE("the engine keeps each particle's id through removals and renumbering") {
  std::vector<Particle> ps;
  for (int i = 0; i < 6; ++i) {
    Particle p;
    p.position = Vec3(0.5 - 0.1 * i, 0.1 * (i % 2), 0);
    p.radius = 0.02;
    p.id = 100 + i;
    ps.push_back(p);
  }
  Device device;
  EngineParams params;
  params.radius = 0.02;
  Engine engine(device, params);
  engine.set_field(test::sphere_grid(1.0, 0.1));
  engine.add_particles(ps);
  engine.remove_particles({1, 4});  // 5 moves into 4's place... swap with last
  const std::vector<size_t> order = engine.sort_by_cells();
  CHECK(order != std::vector<size_t>{0, 1, 2, 3});  // the test renumbers something
  std::map<uint64_t, Vec3> at;
  for (const Particle& p : engine.read_particles()) at[p.id] = p.position;
  REQUIRE(at.size() == 4);
  for (int i : {0, 2, 3, 5}) {
    CHECK(at.at(100 + i).x == doctest::Approx(ps[i].position.x));
    CHECK(at.at(100 + i).y == doctest::Approx(ps[i].position.y));
  }
}
