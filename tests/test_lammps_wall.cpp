// The LAMMPS engine's wall computed from the mesh (issue 31, step 3:
// ExactField, src/lammps/band_field.hpp): each rank computes the bricks of
// the field near the wall where its own spheres reach, and no process holds
// the whole field. ctest runs this file as it is (one process) and under
// `mpirun -np 2` (mpi2.test_lammps_wall). Without LAMMPS built in, each
// case says it is skipped.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "lammps_fixtures.hpp"
#include "skip.hpp"
#include "pfill/boundary.hpp"
#include "pfill/engine/reference.hpp"
#include "pfill/exact_field.hpp"
#include "pfill/fill.hpp"
#include "pfill/lammps.hpp"
#include "pfill/sdf.hpp"
#include "pfill/shapes.hpp"

using namespace pfill;

namespace {

constexpr double kBall = 0.5;

using test::small_params;

/// The field's layout for the ball mesh: exact everywhere, so the whole
/// grid holds the values the bricks compute.
SdfOptions exact_everywhere() {
  SdfOptions o(0.02);
  o.band = std::numeric_limits<double>::infinity();
  return o;
}

/// Spheres on a jittered lattice filling the ball, moving, the outermost
/// within a radius of the wall (pushed from the first step).
std::vector<Particle> ball_lattice() {
  std::vector<Particle> ps = test::jittered_lattice(kBall, 0.098, 7, 0.08, 1);
  for (Particle& p : ps) p.position = p.position * 1.06;
  return ps;
}

/// The bytes of every brick of 4^3 cells (512 B each) whose centre lies
/// less than `band` plus its half diagonal inside: all the bricks one
/// process could need, as band_field.hpp lays them out, plus its index.
uint64_t band_bytes(const ExactField& exact, double band) {
  const ScalarGrid& g = exact.lattice();
  const double half_diagonal = 2 * std::sqrt(3.0) * g.spacing;
  uint64_t bricks = 0, all = 0;
  for (int k = 0; k < g.dims[2] - 1; k += 4)
    for (int j = 0; j < g.dims[1] - 1; j += 4)
      for (int i = 0; i < g.dims[0] - 1; i += 4, ++all)
        bricks += exact.at(g.point(i, j, k) + Vec3(2, 2, 2) * g.spacing) > -(band + half_diagonal);
  return bricks * 512 + all * 4;
}

}  // namespace

TEST_CASE("lammps wall: computed from the mesh, the steps of the reference engine on the whole field") {
  if (!lammps_available()) PFILL_SKIP("this pfill was built without LAMMPS");
  const Mesh ball = make_icosphere(kBall, 4);
  const Boundary boundary(ball);
  const ScalarGrid whole = build_signed_distance_field(boundary, exact_everywhere());
  const ExactField exact(boundary, exact_everywhere());
  REQUIRE(exact.lattice().dims == whole.dims);
  CHECK(exact.lattice().origin.x == whole.origin.x);
  CHECK(exact.at(3, 4, 5) == doctest::Approx(whole.at(3, 4, 5)).epsilon(1e-6));
  const std::vector<Particle> start = ball_lattice();
  REQUIRE(start.size() > 200);
  size_t pushed = 0;  // spheres the wall acts on from the first step
  for (const Particle& p : start) pushed += kBall - length(p.position) < p.radius;
  CHECK(pushed > 20);

  ReferenceEngine ref(small_params());
  ref.set_field(whole);
  ref.add_particles(start);
  std::unique_ptr<ParticleEngine> lmp = make_lammps_engine(small_params());
  lmp->share_exact_field(exact);
  lmp->add_particles(start);
  ref.run_steps(40);
  lmp->run_steps(40);
  const std::vector<StepRecord> hr = ref.read_history(), hl = lmp->read_history();
  REQUIRE(hl.size() == hr.size());
  for (size_t s = 0; s < hr.size(); ++s) {
    CHECK(hl[s].colliding_pairs == hr[s].colliding_pairs);
    CHECK(hl[s].flagged == hr[s].flagged);
  }
  const std::vector<Particle> a = ref.read_particles(), b = lmp->read_particles();
  REQUIRE(a.size() == b.size());
  double worst = 0;
  for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, length(a[i].position - b[i].position));
  INFO("largest position difference " << worst << "; " << pushed << " spheres pushed by the wall at the start");
  CHECK(worst < 1e-6);
}

TEST_CASE("lammps wall: each rank computes only the bricks its spheres reach") {
  if (!lammps_available()) PFILL_SKIP("this pfill was built without LAMMPS");
  const Mesh ball = make_icosphere(kBall, 4);
  const Boundary boundary(ball);
  const ExactField exact(boundary, exact_everywhere());
  const uint64_t whole = static_cast<uint64_t>(exact.lattice().dims[0]) * exact.lattice().dims[1] *
                         exact.lattice().dims[2] * sizeof(float);
  const uint64_t band = band_bytes(exact, 2 * small_params().max_radius);
  std::unique_ptr<ParticleEngine> lmp = make_lammps_engine(small_params());
  lmp->share_exact_field(exact);
  CHECK(lmp->field_bytes() < whole / 32);  // the bricks' index (a word a brick), no brick before a sphere reads one
  lmp->add_particles(ball_lattice());
  lmp->run_steps(20);
  REQUIRE(lmp->read_history().size() == 20);  // (the steps run by now)
  std::vector<uint64_t> bytes{lmp->field_bytes()};
  lmp->gather_over_processes(bytes);  // each rank's, in rank order
  INFO("bytes on rank 0: " << bytes.front() << ", on the last rank " << bytes.back() << "; every brick near the wall "
                            << band << ", the whole grid " << whole);
  for (uint64_t b : bytes) {
    CHECK(b > band / 8);  // every rank's spheres reach the wall
    CHECK(b <= band);     // deep bricks hold nothing
    if (bytes.size() > 1) CHECK(b < 0.75 * static_cast<double>(band));  // the other ranks' part of the wall is not here
  }
}

TEST_CASE("lammps wall: a fill with the wall from the mesh keeps every sphere inside, on a coarser field of its own") {
  if (!lammps_available()) PFILL_SKIP("this pfill was built without LAMMPS");
  FillOptions o;
  o.count = 300;
  o.seed = 2;
  o.colour = ColourOptions{ColourMode::None, {}};
  o.engine = lammps_engine_factory();
  o.finish_on_engine = true;
  FillOptions flat = o;
  o.wall_from_mesh = true;
  const Mesh ball = make_icosphere(1.0, 3);
  const FillResult r = fill(ball, o), f = fill(ball, flat);
  INFO("particles " << r.metrics.count << ", packing " << r.metrics.packing_fraction << ", largest overlap "
                    << r.metrics.max_overlap << "; the whole field's " << f.metrics.count << ", "
                    << f.metrics.packing_fraction);
  CHECK(r.field_spacing == doctest::Approx(2 * f.field_spacing));  // the fill's own field: sites, holes
  CHECK(r.field_bytes < f.field_bytes / 4);
  CHECK(r.metrics.contained_share == 1.0);
  CHECK(r.metrics.max_overlap <= o.max_overlap + 1e-9);
  CHECK(std::abs(static_cast<double>(r.metrics.count) - static_cast<double>(f.metrics.count)) <
        0.05 * static_cast<double>(f.metrics.count));
  CHECK(r.metrics.packing_fraction > 0.5);
}
