// A packing held in parts over MPI ranks (particle_share.hpp, issue 31):
// after a fill on LAMMPS at P > 1 ranks each rank holds its own spheres,
// and the exact check, the metrics and the output work on them through a
// ProcessGroup. Here a set split in two at x = 0.02 (each rank its half)
// must give what the whole set gives in one process: the halos, the
// gather, the metrics, the containment repair and the widest hole. ctest
// runs the file as mpi2.test_lammps_share; at one process (or without
// LAMMPS, whose build brings MPI) each case says it is skipped.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <vector>

#include "pfill/boundary.hpp"
#include "pfill/engine/birth_view.hpp"
#include "pfill/lammps.hpp"
#include "pfill/packing_metrics.hpp"
#include "pfill/particle_share.hpp"
#include "pfill/radius_distribution.hpp"
#include "pfill/shapes.hpp"
#include "skip.hpp"

using namespace pfill;

namespace {

constexpr double kR = 0.1;
constexpr double kVolume = 4.0;  // (any: both sides divide by it)

/// Spheres of radius 0.1 on a jittered lattice of `spacing` in the unit
/// ball, some overlapping, and a ring at the equator whose spheres poke
/// out of the surface by half a radius (the containment repair's work);
/// ids 1, 2, ... The same on every rank. Without the spheres within a
/// spacing of `hole` when it is given (a lattice point and its 6
/// neighbours: a hole ~2 r wide, wider than any near the wall).
ParticleSet packing(double spacing, double jitter, const Vec3* hole = nullptr) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  ParticleSet s;
  auto add = [&s](const Vec3& p) {
    s.positions.push_back(p);
    s.radii.push_back(kR);
    s.ids.push_back(s.size());
  };
  const int n = static_cast<int>(1.0 / spacing) + 1;
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      for (int k = -n; k <= n; ++k) {
        const Vec3 p = Vec3(i, j, k) * spacing + Vec3(u(rng), u(rng), u(rng)) * (jitter * spacing);
        if (length(p) > 1 - 1.2 * kR) continue;
        if (hole && length(p - *hole) < 1.05 * spacing) continue;
        add(p);
      }
  for (int a = 0; a < 24; ++a) {  // crossing the surface by 0.5 r, some pairs closer than 2 r
    const double t = 2 * kPi * a / 24;
    add(Vec3(std::cos(t), std::sin(t), 0.01 * a) * (1 - 0.5 * kR));
  }
  return s;
}

/// Two halves at x = 0.02, each rank one of them (the rule the fill's
/// regions follow: owning_region).
struct Split {
  ParticleShare share;
  ParticleSet own;
};

Split split(const ParticleSet& whole) {
  Split s;
  s.share.group = lammps_process_group();
  Box3 left, right;
  left.lo = {-10, -10, -10}, left.hi = {0.02, 10, 10};
  right.lo = {0.02, -10, -10}, right.hi = {10, 10, 10};
  s.share.regions = {left, right};
  s.share.region = s.share.group->rank();
  for (size_t i = 0; i < whole.size(); ++i)
    if (s.share.owns(whole.positions[i])) {
      s.own.positions.push_back(whole.positions[i]);
      s.own.radii.push_back(whole.radii[i]);
      s.own.ids.push_back(whole.ids[i]);
    }
  return s;
}

/// Whether this run has the two ranks these cases need (MPI started).
bool two_ranks() {
  if (!lammps_available()) return false;
  lammps_mpi_start();
  return lammps_process_group()->size() == 2;
}

const char* kWhy = "needs LAMMPS (MPI) and 2 ranks: ctest runs it as mpi2.test_lammps_share";

}  // namespace

TEST_CASE("particle share: the halo is every other rank's sphere within the reach, with its values") {
  if (!two_ranks()) PFILL_SKIP(kWhy);
  const ParticleSet whole = packing(0.21, 0.05);
  const Split s = split(whole);
  REQUIRE(s.own.size() > 100);
  REQUIRE(s.own.size() < whole.size() - 100);
  std::vector<double> values;  // two a sphere: its id doubled, its x
  for (size_t i = 0; i < s.own.size(); ++i) values.insert(values.end(), {2.0 * s.own.ids[i], s.own.positions[i].x});
  std::vector<double> got;
  const double reach = 0.25;
  const ParticleSet halo = halo_of(s.share, s.own, reach, values, 2, &got);
  std::set<uint64_t> expected, own(s.own.ids.begin(), s.own.ids.end());
  for (size_t i = 0; i < whole.size(); ++i)
    if (!own.count(whole.ids[i]) && distance_to_box(*s.share.mine(), whole.positions[i]) <= reach)
      expected.insert(whole.ids[i]);
  CHECK(expected.size() > 20);
  CHECK(std::set<uint64_t>(halo.ids.begin(), halo.ids.end()) == expected);
  REQUIRE(got.size() == 2 * halo.size());
  size_t wrong = 0;
  for (size_t k = 0; k < halo.size(); ++k)
    wrong += got[2 * k] != 2.0 * halo.ids[k] || got[2 * k + 1] != halo.positions[k].x ||
             halo.positions[k] != whole.positions[halo.ids[k] - 1] || halo.radii[k] != kR;
  CHECK(wrong == 0);
}

TEST_CASE("particle share: the gather gives back the whole set, in id order, to every rank or to the first") {
  if (!two_ranks()) PFILL_SKIP(kWhy);
  const ParticleSet whole = packing(0.21, 0.05);
  Split s = split(whole);
  s.own.colours.assign(s.own.size(), Rgb8{1, 2, 3});
  std::reverse(s.own.positions.begin(), s.own.positions.end());  // (any order in)
  std::reverse(s.own.ids.begin(), s.own.ids.end());
  const ParticleSet all = gather_particles(*s.share.group, s.own, true);
  CHECK(all.positions == whole.positions);
  CHECK(all.ids == whole.ids);
  CHECK(all.radii == whole.radii);
  CHECK(all.colours == std::vector<Rgb8>(whole.size(), Rgb8{1, 2, 3}));
  CHECK_FALSE(all.has_velocities());
  const ParticleSet first = gather_particles(*s.share.group, s.own);
  CHECK(first.size() == (s.share.group->rank() == 0 ? whole.size() : 0));
}

TEST_CASE("particle share: the metrics of the halves are the whole set's") {
  if (!two_ranks()) PFILL_SKIP(kWhy);
  const Boundary boundary(make_icosphere(1.0, 3));
  const ParticleSet whole = packing(0.19, 0.08);  // closer than 2 r: overlapping pairs across the border too
  const Split s = split(whole);
  MetricsOptions mo;
  mo.holes = false;
  const PackingMetrics a = measure_packing(boundary, kVolume, whole, mo);
  const PackingMetrics b = measure_packing(boundary, kVolume, s.own, mo, s.share);
  INFO("whole: " << a.count << " spheres, " << a.overlapping_pairs << " pairs over, largest " << a.max_overlap);
  CHECK(a.overlapping_pairs > 100);
  CHECK(b.count == a.count);
  CHECK(b.overlapping_pairs == a.overlapping_pairs);
  CHECK(b.centres_outside == a.centres_outside);
  CHECK(b.packing_fraction == doctest::Approx(a.packing_fraction).epsilon(1e-12));
  CHECK(b.mean_overlap == doctest::Approx(a.mean_overlap).epsilon(1e-12));
  CHECK(b.max_overlap == a.max_overlap);
  CHECK(b.mean_coordination == doctest::Approx(a.mean_coordination).epsilon(1e-12));
  CHECK(b.min_distance == a.min_distance);
  CHECK(b.contained_share == doctest::Approx(a.contained_share).epsilon(1e-12));
  CHECK(b.max_penetration == a.max_penetration);
}

TEST_CASE("particle share: the containment repair of the halves is the whole set's") {
  if (!two_ranks()) PFILL_SKIP(kWhy);
  const Boundary boundary(make_icosphere(1.0, 3));
  ParticleSet whole = packing(0.21, 0.05);
  Split s = split(whole);
  const ContainmentRepair a = repair_containment(boundary, whole, 0.01, 0.001);
  const ContainmentRepair b = repair_containment(boundary, s.own, 0.01, 0.001, s.share);
  INFO("whole: " << a.moved << " moved, " << a.removed << " removed");
  CHECK(a.moved > 0);
  CHECK(a.moved + a.removed >= 20);  // the ring: moved in, most then press on the lattice and give way
  CHECK(b.moved == a.moved);
  CHECK(b.removed == a.removed);
  const ParticleSet all = gather_particles(*s.share.group, s.own, true);
  CHECK(all.ids == whole.ids);
  CHECK(all.positions == whole.positions);
}

TEST_CASE("particle share: the widest hole of the halves is the whole set's, wherever it lies") {
  if (!two_ranks()) PFILL_SKIP(kWhy);
  const Boundary boundary(make_icosphere(1.0, 3));
  for (const Vec3 at : {Vec3(0.0, 0.21, 0.0), Vec3(0.42, 0.0, 0.21)}) {  // at the border; inside the right half
    const ParticleSet whole = packing(0.21, 0.0, &at);
    const Split s = split(whole);
    const std::vector<Hole> a = largest_holes(boundary, whole, kR);
    const std::vector<Hole> b = largest_holes(boundary, s.own, kR, s.share);
    INFO("whole: " << a.front().gap_over_r << " r at " << a.front().centre.x << " " << a.front().centre.y << " "
                   << a.front().centre.z << "; halves: " << b.front().gap_over_r << " r");
    CHECK(a.front().gap_over_r > 1.5);
    CHECK(length(a.front().centre - at) < 0.5 * kR);
    CHECK(b.front().gap_over_r == doctest::Approx(a.front().gap_over_r).epsilon(0.01));
    CHECK(length(b.front().centre - a.front().centre) < 0.1 * kR);
    size_t close = 0;  // each hole once: none within a radius of another
    for (size_t i = 0; i < b.size(); ++i)
      for (size_t j = i + 1; j < b.size(); ++j) close += length(b[i].centre - b[j].centre) < kR;
    CHECK(close == 0);
  }
}

// The radii's fit to their distribution (compare_distribution with a
// share): the class shares and moments are sums over the halves, and the
// Kolmogorov-Smirnov distance is exact (the few quantile bins where it may
// lie gathered), not a histogram's estimate: it must equal the whole set's
// to rounding. Radii drawn off the law (a skewed quantile, and a run at
// the smallest radius, where a truncated law starts from its left), so the
// distance is not small.
TEST_CASE("particle share: the radii's fit of the halves is the whole set's") {
  if (!two_ranks()) PFILL_SKIP(kWhy);
  for (const char* spec : {"lognormal:1,0.2", "uniform:0.5,1", "discrete:1:0.3,2:0.7"}) {
    const RadiusDistribution d = RadiusDistribution::parse(spec);
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(0, 1), x(-1, 1);
    ParticleSet whole;
    for (size_t i = 0; i < 20000; ++i) {
      whole.positions.push_back({x(rng), x(rng), x(rng)});
      const double q = u(rng);
      whole.radii.push_back(i % 50 == 0 ? d.min_radius() : d.quantile(std::pow(q, 1.15)));
      whole.ids.push_back(i + 1);
    }
    const Split s = split(whole);
    const DistributionFit a = compare_distribution(d, whole.radii);
    const DistributionFit b = compare_distribution(d, s.own.radii, s.share);
    INFO(std::string(spec) << ": whole " << a.describe() << "; halves " << b.describe());
    CHECK(a.distance > 0.01);
    CHECK(b.class_error == a.class_error);
    CHECK(b.distance == doctest::Approx(a.distance).epsilon(1e-12));
    CHECK(b.mean == doctest::Approx(a.mean).epsilon(1e-12));
    CHECK(b.stddev == doctest::Approx(a.stddev).epsilon(1e-9));
    CHECK(b.skewness == doctest::Approx(a.skewness).epsilon(1e-9));
    REQUIRE(b.classes.size() == a.classes.size());
    for (size_t k = 0; k < a.classes.size(); ++k) {
      CHECK(b.classes[k].achieved_number == doctest::Approx(a.classes[k].achieved_number).epsilon(1e-12));
      CHECK(b.classes[k].achieved_volume == doctest::Approx(a.classes[k].achieved_volume).epsilon(1e-12));
    }
  }
}
