// The OpenCL engine's hold (ParticleEngine::hold, src/engine/engine_hold.*):
// only the moving spheres move, the held ones stay put and push, the rest
// are not stepped at all; every count, read and mass stays the whole
// packing's; a release, an addition or a removal steps them all again.
#include <doctest/doctest.h>

#include <cmath>
#include <map>
#include <vector>

#include "engine_fixtures.hpp"
#include "pfill/device/device.hpp"
#include "pfill/engine/engine.hpp"

using namespace pfill;
using namespace pfill::test;

namespace {

using Part = ParticleEngine::StepPart;

// Moving within 1.5 of the origin, held within 3, out beyond.
Part part_by_distance(const Vec3& p) { return length(p) < 1.5 ? Part::moving : length(p) < 3 ? Part::held : Part::out; }

struct Held {
  EngineParams params;
  ScalarGrid field;
  std::vector<Particle> start;  // each with its index as its id
  Held() : field(box_grid({6, 6, 6}, 0.2)) {
    params = test_params();
    params.radius = 0.5;
    params.damping = 0.1;
    const Vec3 h{6, 6, 6};
    start = random_particles(400, 0.5, 6, 1.1, 0.5, 5, [h](const Vec3& x) { return box_distance(x, h); });
    // an overlapping pair at the origin, at rest, the others clear of it: a jam for the moving spheres
    std::vector<Particle> kept;
    for (const Particle& p : start)
      if (length(p.position) > 1.6) kept.push_back(p);
    start = kept;
    Particle a;
    a.radius = 0.5;
    a.position = {-0.3, 0, 0};
    Particle b = a;
    b.position = {0.3, 0, 0};
    start.push_back(a);
    start.push_back(b);
    for (size_t i = 0; i < start.size(); ++i) start[i].id = i;
  }
  std::map<uint64_t, Particle> by_id(const std::vector<Particle>& ps) const {
    std::map<uint64_t, Particle> m;
    for (const Particle& p : ps) m[p.id] = p;
    return m;
  }
};

}  // namespace

TEST_CASE("engine hold: only the moving spheres move, the held stay put, the rest are not stepped") {
  Held t;
  Engine engine(shared_device(), t.params);
  engine.set_field(t.field);
  engine.add_particles(t.start);
  engine.run_steps(3);
  const auto before = t.by_id(engine.read_particles());
  size_t moving = 0, held = 0, fast_out = 0;
  for (const auto& [id, p] : before) {
    const Part part = part_by_distance(p.position);
    moving += part == Part::moving;
    held += part == Part::held;
    fast_out += part == Part::out && length(p.velocity) > 0;
  }
  REQUIRE(moving >= 2);
  REQUIRE(held > 10);
  REQUIRE(fast_out > 10);
  const std::optional<size_t> taking = engine.hold(part_by_distance);
  REQUIRE(taking);
  CHECK(*taking == moving + held);
  CHECK(engine.size() == before.size());
  engine.run_steps(40);
  const auto during = t.by_id(engine.read_particles());
  REQUIRE(during.size() == before.size());
  size_t moved = 0;
  for (const auto& [id, p] : before) {
    const Particle& q = during.at(id);
    INFO("sphere " << id << " at " << p.position.x << " " << p.position.y << " " << p.position.z);
    CHECK(std::abs(q.mass - p.mass) <= 1e-6 * p.mass);  // its own mass, whatever the hold gives it
    switch (part_by_distance(p.position)) {
      case Part::out:  // not stepped: not a bit changed
        CHECK(q.position == p.position);
        CHECK(q.velocity == p.velocity);
        break;
      case Part::held:
        CHECK(q.position == p.position);
        CHECK(length(q.velocity) < 1e-20);  // (a force on a mass of 1e30)
        break;
      case Part::moving:
        moved += q.position != p.position;
        break;
    }
  }
  CHECK(moved >= 2);
  engine.release_hold();
  CHECK(engine.size() == before.size());
  engine.run_steps(5);
  size_t out_moved = 0;
  for (const auto& [id, q] : t.by_id(engine.read_particles()))
    out_moved += part_by_distance(before.at(id).position) == Part::out && q.position != during.at(id).position;
  CHECK(out_moved >= fast_out / 2);  // all stepped again
}

TEST_CASE("engine hold: a sort renumbers those taking part among themselves; a removal steps them all again") {
  Held t;
  Engine engine(shared_device(), t.params);
  engine.set_field(t.field);
  engine.add_particles(t.start);
  const std::optional<size_t> taking = engine.hold(part_by_distance);
  REQUIRE(taking);
  const std::vector<Particle> held = engine.read_particles();
  const std::vector<size_t> order = engine.sort_by_cells();
  REQUIRE(order.size() == held.size());
  const std::vector<Particle> sorted = engine.read_particles();
  for (size_t k = 0; k < order.size(); ++k) {
    INFO("index " << k);
    CHECK(sorted[k].id == held[order[k]].id);
    if (k >= *taking) CHECK(order[k] == k);  // the rest where they were
    else CHECK(order[k] < *taking);
  }
  engine.remove_particles({0});
  CHECK(engine.size() == held.size() - 1);
  const auto before = t.by_id(engine.read_particles());
  engine.run_steps(5);
  size_t out_moved = 0;
  for (const auto& [id, q] : t.by_id(engine.read_particles()))
    out_moved += part_by_distance(before.at(id).position) == Part::out && q.position != before.at(id).position;
  CHECK(out_moved > 10);
}
