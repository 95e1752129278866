// The contact network (include/pfill/contact_network.hpp): pairs within the
// gap against a brute-force O(N^2) search on generated sets, wall contacts
// in a cube, and the network in every particle format and the contacts CSV.
#include <doctest/doctest.h>

#include <algorithm>
#include <random>
#include <set>
#include <utility>

#include "particle_fixtures.hpp"
#include "pfill/boundary.hpp"
#include "pfill/contact_network.hpp"
#include "pfill/error.hpp"
#include "pfill/particle_io.hpp"
#include "pfill/shapes.hpp"

using namespace pfill;
using pfill::test::ScratchDir;
using pfill::test::read_text;

namespace {

// Spheres of radius about r on a jittered cubic lattice at spacing 2r, so
// that centre distances straddle the contact distance; radii vary by +-spread.
ParticleSet near_touching(int side, double r, double spread, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.03 * r, 0.03 * r), scale(1 - spread, 1 + spread);
  ParticleSet set;
  for (int i = 0; i < side; ++i)
    for (int j = 0; j < side; ++j)
      for (int k = 0; k < side; ++k) {
        set.positions.push_back(Vec3(i, j, k) * (2 * r) + Vec3(jitter(rng), jitter(rng), jitter(rng)) -
                                Vec3(side * r, side * r, side * r));
        set.radii.push_back(r * scale(rng));
      }
  return set;
}

std::set<std::pair<uint32_t, uint32_t>> brute_force(const ParticleSet& p, double gap_fraction) {
  std::set<std::pair<uint32_t, uint32_t>> out;
  for (uint32_t i = 0; i < p.size(); ++i)
    for (uint32_t j = i + 1; j < p.size(); ++j) {
      const double gap = length(p.positions[j] - p.positions[i]) - p.radii[i] - p.radii[j];
      if (gap <= gap_fraction * std::min(p.radii[i], p.radii[j])) out.insert({i, j});
    }
  return out;
}

void check_against_brute_force(const ParticleSet& p, double gap_fraction) {
  const ContactNetwork net = find_contacts(p, gap_fraction);
  const auto expected = brute_force(p, gap_fraction);
  REQUIRE(net.pairs.size() == expected.size());
  std::set<std::pair<uint32_t, uint32_t>> got;
  std::vector<uint32_t> coordination(p.size(), 0);
  for (size_t k = 0; k < net.pairs.size(); ++k) {
    const PairContact& c = net.pairs[k];
    CHECK(c.a < c.b);
    if (k) CHECK(std::make_pair(net.pairs[k - 1].a, net.pairs[k - 1].b) < std::make_pair(c.a, c.b));
    CHECK(c.gap == doctest::Approx(length(p.positions[c.b] - p.positions[c.a]) - p.radii[c.a] - p.radii[c.b]));
    got.insert({c.a, c.b});
    ++coordination[c.a], ++coordination[c.b];
  }
  CHECK(got == expected);
  CHECK(net.coordination == coordination);
  CHECK(net.mean_coordination() == doctest::Approx(2.0 * expected.size() / p.size()));
}

}  // namespace

TEST_CASE("contacts: the pairs within the gap equal a brute-force search") {
  SUBCASE("one radius, a jittered lattice (many pairs at the threshold)") {
    const ParticleSet p = near_touching(9, 0.1, 0.0, 3);
    check_against_brute_force(p, 0.02);
    check_against_brute_force(p, 0.0);
    check_against_brute_force(p, 0.05);
    CHECK(find_contacts(p, 0.05).pairs.size() > p.size());  // the test has pairs to find
  }
  SUBCASE("radii of several sizes") {
    check_against_brute_force(near_touching(8, 0.1, 0.15, 4), 0.02);
    check_against_brute_force(test::random_particles(1500, 5, false, false), 1.0);
  }
  SUBCASE("nothing, one particle") {
    CHECK(find_contacts(ParticleSet{}).pairs.empty());
    ParticleSet one;
    one.positions.push_back({0, 0, 0});
    one.radii.push_back(1);
    const ContactNetwork net = find_contacts(one);
    CHECK(net.pairs.empty());
    CHECK(net.coordination == std::vector<uint32_t>{0});
  }
  SUBCASE("a gap outside [0, 1] is refused") {
    CHECK_THROWS_AS(find_contacts(near_touching(2, 0.1, 0, 1), -0.1), Error);
    CHECK_THROWS_AS(find_contacts(near_touching(2, 0.1, 0, 1), 2), Error);
  }
}

TEST_CASE("contacts: spheres touching the wall, with the surface point and its outward normal") {
  const Boundary boundary(make_cube(1.0));
  ParticleSet p;
  const double r = 0.1;
  p.positions = {{0, 0, 0}, {1 - r, 0, 0}, {0, -(1 - r * 1.01), 0}, {0, 0, 1 - r * 1.05}, {1 - r, 1 - r, 0}};
  p.radii.assign(p.positions.size(), r);
  ContactNetwork net = find_contacts(p, 0.02);
  find_wall_contacts(net, p, boundary);
  REQUIRE(net.wall.size() == 3);  // touching, a gap of 1% r, and a corner sphere; not the 5% one
  CHECK(net.wall[0].particle == 1);
  CHECK(net.wall[0].point.x == doctest::Approx(1));
  CHECK(net.wall[0].normal.x == doctest::Approx(1));
  CHECK(net.wall[0].gap == doctest::Approx(0).epsilon(1e-12));
  CHECK(net.wall[1].particle == 2);
  CHECK(net.wall[1].normal.y == doctest::Approx(-1));
  CHECK(net.wall[1].gap == doctest::Approx(0.01 * r));
  CHECK(net.wall[2].particle == 4);
  const nlohmann::ordered_json j = contacts_report_json(net, p, &boundary);
  CHECK(j["wall_contacts"] == 3);
  CHECK(j["all_within_gap"] == true);
  CHECK(j["coordination_by_depth"].size() >= 1);
}

TEST_CASE("contacts: every format carries them, the CSV lists pairs and wall contacts") {
  ScratchDir dir("contacts");
  ParticleSet p = near_touching(4, 0.1, 0.0, 7);
  for (size_t i = 0; i < p.size(); ++i) p.ids.push_back(100 + i);
  const ContactNetwork net = find_contacts(p, 0.02);
  REQUIRE(net.pairs.size() > 10);
  ParticleWriteOptions wo;
  wo.contacts = &net;
  const std::string m = std::to_string(net.pairs.size());

  write_particles(p, dir / "c.ply", wo);
  const std::string ply = read_text(dir / "c.ply");
  CHECK(ply.find("property ushort coordination\nelement edge " + m +
                 "\nproperty int vertex1\nproperty int vertex2\nproperty float gap\nend_header") != std::string::npos);
  const ParticleSet back = read_particles(dir / "c.ply");  // readers skip the edges
  CHECK(back.size() == p.size());
  CHECK(back.positions[5].x == doctest::Approx(p.positions[5].x).epsilon(1e-6));

  write_particles(p, dir / "c.vtp", wo);
  const std::string vtp = read_text(dir / "c.vtp");
  CHECK(vtp.find("NumberOfLines=\"" + m + "\"") != std::string::npos);
  CHECK(vtp.find("Name=\"coordination\"") != std::string::npos);
  CHECK(vtp.find("<Lines>") != std::string::npos);

  write_particles(p, dir / "c.data", wo);
  const std::string data = read_text(dir / "c.data");
  CHECK(data.find(m + " bonds\n1 bond types\n") != std::string::npos);
  CHECK(data.find("Atoms # hybrid sphere bond") != std::string::npos);
  CHECK(data.find("\nBonds\n\n1 1 " + std::to_string(p.id(net.pairs[0].a)) + " " +
                  std::to_string(p.id(net.pairs[0].b)) + "\n") != std::string::npos);

  write_particles(p, dir / "c.csv", wo);
  CHECK(read_text(dir / "c.csv").rfind("x,y,z,radius,id,coordination\n", 0) == 0);
  write_particles(p, dir / "c.xyzr", wo);
  CHECK(read_text(dir / "c.xyzr").find("# x y z r id coordination\n") != std::string::npos);

  write_particles(p, dir / "c.glb", wo);
  CHECK(read_text(dir / "c.glb").find("\"_COORDINATION\"") != std::string::npos);

  write_contacts_csv(p, net, dir / "pairs.csv");
  const std::string csv = read_text(dir / "pairs.csv");
  CHECK(static_cast<size_t>(std::count(csv.begin(), csv.end(), '\n')) == net.pairs.size() + 1);
  CHECK(csv.rfind("a,b,gap,x,y,z,nx,ny,nz\n" + std::to_string(p.id(net.pairs[0].a)) + ",", 0) == 0);

  ContactNetwork wrong = net;
  wrong.coordination.pop_back();
  wo.contacts = &wrong;
  CHECK_THROWS_AS(write_particles(p, dir / "bad.ply", wo), Error);
}
