// SizeDeficit: which size class the next sphere takes (src/fill/size_deficit.hpp).
#include <doctest/doctest.h>

#include "fill/size_deficit.hpp"
#include "pfill/radius_distribution.hpp"

using namespace pfill;

TEST_CASE("size classes: the one furthest below its share goes first") {
  SizeDeficit d(RadiusDistribution::parse("discrete:1:0.5,2:0.5"));
  REQUIRE(d.classes() == 2);
  CHECK(d.candidates().front() == 1);  // a tie: the larger
  d.add(2);
  CHECK(d.candidates().front() == 0);
  d.add(1);
  d.add(1);
  CHECK(d.candidates().front() == 1);
}

TEST_CASE("size classes: rare large spheres are born first, then the shares rule again") {
  // 1:10 at half the volume each: one large sphere in 1,001 by number.
  const auto mix = RadiusDistribution::parse("discrete:1:0.5,10:0.5", FractionBasis::Volume);
  SizeDeficit plain(mix);
  CHECK(plain.candidates().front() == 0);  // by number the small ones lead for ~1,000 births

  SizeDeficit d(mix);
  d.front_load(4000, 25);  // ~4 large expected, fewer than a wave's sites
  for (int i = 0; i < 4; ++i) {
    REQUIRE(d.candidates().front() == 1);
    d.add(10);
  }
  CHECK(d.candidates().front() == 0);
  d.add(1);
  CHECK(d.candidates().front() == 0);

  // Common classes are not front-loaded: half the number each stays interleaved.
  SizeDeficit even(RadiusDistribution::parse("discrete:1:0.5,2:0.5"));
  even.front_load(16000, 25);
  even.add(2);
  CHECK(even.candidates().front() == 0);
}

TEST_CASE("size classes: a rare class loses no sphere below its share, a common one may lose one") {
  SizeDeficit d(RadiusDistribution::parse("discrete:1:0.5,10:0.5", FractionBasis::Volume));
  for (int i = 0; i < 3996; ++i) d.add(1);
  for (int i = 0; i < 4; ++i) d.add(10);
  CHECK_FALSE(d.may_lose(1));  // 4 of 3.996 expected: a fifth of its volume would go
  CHECK(d.may_lose(0));
  SizeDeficit even(RadiusDistribution::parse("discrete:1:0.5,2:0.5"));
  for (int i = 0; i < 100; ++i) even.add(1), even.add(2);
  CHECK(even.may_lose(1));  // 99 of 99.5: within one sphere
}

TEST_CASE("size classes: when the rare large fall short, the others are held to their shares of those placed") {
  // 1:10 at half the volume each, 4 large expected, 2 placed: 2,000 small.
  const auto mix = RadiusDistribution::parse("discrete:1:0.5,10:0.5", FractionBasis::Volume);
  SizeDeficit d(mix);
  d.front_load(4000, 16);
  std::mt19937_64 rng(1);
  REQUIRE(d.front_radii(rng).size() == 4);
  d.add(10);
  d.add(10);
  const std::vector<size_t> caps = d.caps_held_to_front({10, 10});
  REQUIRE(caps.size() == 2);
  CHECK(caps[0] == 2000);
  CHECK(caps[1] == 2);
  // All 4 placed: no caps, unless the radii were shrunk (always).
  SizeDeficit full(mix);
  full.front_load(4000, 16);
  for (int i = 0; i < 4; ++i) full.add(10);
  CHECK(full.caps_held_to_front({10, 10, 10, 10}).empty());
  CHECK(full.caps_held_to_front({10, 10, 10, 10}, true) == std::vector<size_t>{4000, 4});

  d.set_caps(caps);
  d.end_front_load();
  std::vector<double> radii(1999, 1.0);
  radii.push_back(10);
  radii.push_back(10);
  d.recount(radii);
  CHECK(!d.all_capped());
  CHECK(d.candidates() == std::vector<size_t>{0});  // the large class is full
  CHECK(d.take_within(5, rng) == 1.0);
  CHECK(d.all_capped());
  CHECK(d.candidates().empty());
  CHECK(d.take_within(5, rng) == 0);  // no hole takes a sphere any more
}
