// A wave's newborns decided per process (src/fill/wave_choice.hpp, issue
// 31): processes that each decide their own sites, told only the others'
// open wave sites near their borders, take together the newborns one
// process takes, whatever the split; the places and ids follow the
// processes' order, and "the newest" is the wave's largest key at any
// process count.
#include <doctest/doctest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "fill/wave_choice.hpp"

using namespace pfill;

namespace {

constexpr double kClearance = 1.0;

// Open wave sites 5 apart (jittered) and room sites 1.5 apart, each open
// with probability 1/2, over a 12-wide cube; keys in lattice order, rooms after.
struct Wave {
  std::vector<OpenSite> open, rooms;
};

Wave random_wave(uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  std::bernoulli_distribution coin(0.5);
  Wave w;
  uint64_t key = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k, ++key)
        if (coin(rng)) w.open.push_back({key, Vec3(1 + 5 * i + u(rng), 1 + 5 * j + u(rng), 1 + 5 * k + u(rng))});
  key = 1000;
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j)
      for (int k = 0; k < 8; ++k, ++key)
        if (coin(rng)) w.rooms.push_back({key, Vec3(0.5 + 1.5 * i, 0.5 + 1.5 * j, 0.5 + 1.5 * k)});
  return w;
}

std::vector<uint64_t> keys_of(std::vector<OpenSite> sites) {
  std::vector<uint64_t> keys;
  for (const OpenSite& s : sites) keys.push_back(s.key);
  std::sort(keys.begin(), keys.end());
  return keys;
}

// The cube cut into `cuts` slabs along x and, when `two_axes`, in two along y.
std::vector<Box3> regions_of(int cuts, bool two_axes) {
  std::vector<Box3> regions;
  const double w = 12.0 / cuts;
  for (int c = 0; c < cuts; ++c)
    for (int h = 0; h < (two_axes ? 2 : 1); ++h) {
      const double y0 = two_axes ? 6.0 * h : 0.0, y1 = two_axes ? 6.0 * (h + 1) : 12.0;
      regions.push_back(Box3{{w * c, y0, 0}, {w * (c + 1), y1, 12}});
    }
  return regions;
}

struct Split {
  std::vector<std::vector<OpenSite>> chosen;  ///< each process's newborns
  size_t told_sites = 0;                      ///< the border sites told, over all processes
};

// Each process: its own sites, the border words of all (a gather), its choice.
Split split_choice(const Wave& w, const std::vector<Box3>& regions, bool tell) {
  std::vector<BirthView> views(regions.size());
  std::vector<uint64_t> told;
  std::vector<std::vector<OpenSite>> open(regions.size()), rooms(regions.size());
  for (size_t r = 0; r < regions.size(); ++r) {
    views[r].regions = regions;
    views[r].region = static_cast<int>(r);
    for (const OpenSite& s : w.open)
      if (views[r].decides(s.position)) open[r].push_back(s);
    for (const OpenSite& s : w.rooms)
      if (views[r].decides(s.position)) rooms[r].push_back(s);
    const std::vector<uint64_t> words = border_site_words(views[r], open[r], kClearance);
    told.insert(told.end(), words.begin(), words.end());
  }
  Split out;
  out.told_sites = told.size() / 4;
  for (size_t r = 0; r < regions.size(); ++r)
    out.chosen.push_back(choose_wave(open[r], rooms[r], tell ? sites_of_words(told) : std::vector<OpenSite>{}, kClearance));
  return out;
}

}  // namespace

TEST_CASE("wave choice: one process takes every open wave site, then the room sites clear of the wave") {
  const Wave w = random_wave(1);
  REQUIRE(w.open.size() > 5);
  const std::vector<OpenSite> chosen = choose_wave(w.open, w.rooms, {}, kClearance);
  // The wave sites first, all of them, in their order.
  REQUIRE(chosen.size() > w.open.size());
  for (size_t k = 0; k < w.open.size(); ++k) CHECK(chosen[k].key == w.open[k].key);
  // Each room site taken lies clear of every other newborn; each one left
  // out lies within the clearance of a newborn.
  size_t left_out = 0;
  for (const OpenSite& s : w.rooms) {
    const bool taken = std::any_of(chosen.begin(), chosen.end(), [&](const OpenSite& c) { return c.key == s.key; });
    const bool near = std::any_of(chosen.begin(), chosen.end(),
                                  [&](const OpenSite& c) { return c.key != s.key && length(c.position - s.position) < kClearance; });
    CHECK(taken != near);
    left_out += !taken;
  }
  CHECK(left_out > 0);
}

TEST_CASE("wave choice: room sites closer than their clearance take the first in key order") {
  const std::vector<OpenSite> rooms = {{10, Vec3(0, 0, 0)}, {11, Vec3(0.5, 0, 0)}, {12, Vec3(1.2, 0, 0)}};
  const std::vector<OpenSite> chosen = choose_wave({}, rooms, {}, kClearance);
  CHECK(keys_of(chosen) == std::vector<uint64_t>{10, 12});
}

TEST_CASE("wave choice: processes told the border sites take together what one process takes") {
  int blind_differs = 0;
  for (uint32_t seed = 1; seed <= 4; ++seed) {
    const Wave w = random_wave(seed);
    const std::vector<uint64_t> whole = keys_of(choose_wave(w.open, w.rooms, {}, kClearance));
    for (const auto& [cuts, two_axes] : {std::pair{2, false}, std::pair{3, false}, std::pair{2, true}, std::pair{5, true}}) {
      CAPTURE(seed);
      CAPTURE(cuts);
      CAPTURE(two_axes);
      const std::vector<Box3> regions = regions_of(cuts, two_axes);
      const Split split = split_choice(w, regions, true);
      std::vector<OpenSite> all;
      for (size_t r = 0; r < regions.size(); ++r) {
        // Each process's newborns are its own, wave sites first, each part in key order.
        BirthView v;
        v.regions = regions;
        v.region = static_cast<int>(r);
        for (const OpenSite& s : split.chosen[r]) CHECK(v.decides(s.position));
        all.insert(all.end(), split.chosen[r].begin(), split.chosen[r].end());
      }
      CHECK(keys_of(all) == whole);
      // Only the border sites travel: fewer than all the open wave sites
      // (some where a cut runs through the wave sites' rows, x = 6 or y = 6).
      if (cuts == 2 || two_axes) CHECK(split.told_sites > 0);
      CHECK(split.told_sites < w.open.size());
      // Untold, a room site near a border would ignore a newborn beyond it.
      const Split untold = split_choice(w, regions, false);
      std::vector<OpenSite> blind;
      for (const auto& c : untold.chosen) blind.insert(blind.end(), c.begin(), c.end());
      blind_differs += keys_of(blind) != whole;
    }
  }
  CHECK(blind_differs > 0);
}

TEST_CASE("wave choice: places and ids in the processes' order, the newest the largest key") {
  // Three processes' (count, largest key): 2 newborns up to key 40, none, 3 up to key 25.
  const std::vector<uint64_t> words = {2, 40, 0, 0, 3, 25};
  const WaveShare a = wave_share_of(words, 0), b = wave_share_of(words, 1), c = wave_share_of(words, 2);
  CHECK(a.first == 0);
  CHECK(b.first == 2);
  CHECK(c.first == 2);
  for (const WaveShare& s : {a, b, c}) {
    CHECK(s.total == 5);
    CHECK(s.newest == 1);  // the first process's last: key 40
  }
  // The same wave on one process: the newest is the last.
  CHECK(wave_share_of({5, 40}, 0).newest == 4);
  CHECK(wave_share_of({0, 0}, 0).total == 0);
}
