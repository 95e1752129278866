// The newborns' counter-based generator (src/fill/counter_rng.hpp): a pure
// function of (seed, wave, site, stream), so any engine and any MPI rank
// draw the same newborn for the same site and wave.
#include <doctest/doctest.h>

#include <cmath>
#include <set>
#include <vector>

#include "fill/counter_rng.hpp"

using namespace pfill;

namespace {

std::vector<uint64_t> draws(CounterRng g, int n) {
  std::vector<uint64_t> out;
  for (int k = 0; k < n; ++k) out.push_back(g());
  return out;
}

}  // namespace

TEST_CASE("counter rng: the same key draws the same, any other key draws otherwise") {
  const std::vector<uint64_t> a = draws(CounterRng(1, 48, 17), 8);
  CHECK(a == draws(CounterRng(1, 48, 17), 8));
  CHECK(a == draws(CounterRng(1, 48, 17, 0), 8));
  CHECK(a != draws(CounterRng(1, 48, 18), 8));   // the next site
  CHECK(a != draws(CounterRng(1, 96, 17), 8));   // the next wave
  CHECK(a != draws(CounterRng(2, 48, 17), 8));   // another seed
  CHECK(a != draws(CounterRng(1, 48, 17, 1), 8));  // the radius' stream
  // Keys that swap places are other streams too.
  CHECK(draws(CounterRng(1, 2, 3), 4) != draws(CounterRng(1, 3, 2), 4));
  // Neighbouring sites' first draws share no value over many sites and waves.
  std::set<uint64_t> first;
  for (uint64_t wave = 0; wave < 50; ++wave)
    for (uint64_t site = 0; site < 200; ++site) first.insert(CounterRng(5, wave, site)());
  CHECK(first.size() == 50 * 200);
}

TEST_CASE("counter rng: uniform draws and directions over neighbouring sites") {
  // One draw from each of many neighbouring sites' streams: as uniform as a
  // long stream (mean 1/2, variance 1/12), directions on the unit sphere
  // with no preferred axis.
  const int n = 20000;
  double sum = 0, sq = 0;
  Vec3 mean_dir;
  double zz = 0;
  for (int k = 0; k < n; ++k) {
    CounterRng g(3, 144, static_cast<uint64_t>(k));
    const double u = g.uniform();
    CHECK(u >= 0);
    CHECK(u < 1);
    sum += u, sq += u * u;
    const Vec3 d = g.direction();
    CHECK(std::abs(length(d) - 1) < 1e-12);
    mean_dir += d;
    zz += d.z * d.z;
  }
  const double mean = sum / n, var = sq / n - mean * mean;
  CHECK(std::abs(mean - 0.5) < 0.01);
  CHECK(std::abs(var - 1.0 / 12) < 0.005);
  CHECK(length(mean_dir / n) < 0.03);
  CHECK(std::abs(zz / n - 1.0 / 3) < 0.01);  // <z^2> = 1/3 on the sphere
}
