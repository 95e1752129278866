// The device's profiling (PFILL_PROFILE=1: a fill's per-pass kernel and
// transfer seconds). Apart from test_engine_small, which oclgrind runs: a
// second device and context in that run made oclgrind report reads past
// the field in `advance` that neither test case makes alone.
#include <doctest/doctest.h>

#include "engine_fixtures.hpp"
#include "pfill/device/device.hpp"
#include "pfill/engine/engine.hpp"

using namespace pfill;
using namespace pfill::test;

TEST_CASE("a profiling device times the engine's kernels and transfers (PFILL_PROFILE's per-pass figures)") {
  Device device("", /*profiling=*/true);
  EngineParams p = test_params();
  const double R = 2.5;
  Engine engine(device, p);
  engine.set_field(sphere_grid(R, 0.25));
  const DeviceTimes before = device.times();
  const auto ps = random_particles(30, 0.5, R, 1.0, 1.0, 21, [R](const Vec3& x) { return sphere_distance(x, R); });
  engine.add_particles(ps);  // a write
  engine.run_steps(10);      // launches
  engine.read_history();     // a read
  engine.read_particles();   // reads
  const DeviceTimes after = device.times();
  CHECK(after.kernels >= before.kernels + 10);
  CHECK(after.transfers >= before.transfers + 3);
  CHECK(after.kernel_seconds > before.kernel_seconds);
  CHECK(after.transfer_seconds >= before.transfer_seconds);
  CHECK(device.times().kernels == after.kernels);  // nothing new queued
  // The split by kernel name adds up to the kernels' total, and names the
  // step's kernels (the CPU form's pair_forces, or the GPU form's).
  double split = 0;
  for (const auto& [name, seconds] : after.by_kernel) {
    CHECK(!name.empty());
    CHECK(seconds >= 0);
    split += seconds;
  }
  CHECK(split == doctest::Approx(after.kernel_seconds).epsilon(1e-9));
  CHECK(after.by_kernel.count("advance") == 1);
  CHECK(after.by_kernel.at("advance") > 0);
  // Without profiling: nothing is counted.
  Device plain;
  CHECK(plain.times().kernels == 0);
  CHECK(plain.times().kernel_seconds == 0);
}
