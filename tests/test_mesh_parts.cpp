// The closed parts of a mesh from its triangles (src/fill/mesh_parts.hpp),
// and a site for each part that has none where no field is built
// (src/fill/part_sites.hpp; issue 31).
#include <doctest/doctest.h>

#include <set>

#include "bad_meshes.hpp"
#include "fill/mesh_parts.hpp"
#include "fill/part_sites.hpp"
#include "pfill/boundary.hpp"
#include "pfill/mesh_diagnostics.hpp"

using namespace pfill;
using namespace pfill::test;

namespace {

Mesh turned_inside_out(Mesh m) {
  for (Triangle& t : m.triangles) std::swap(t[1], t[2]);
  return m;
}

// A hollow ball (a shell from 0.6 to 1), a ball of 0.3 in its cavity, and
// a ball of 0.5 apart: components shell, cavity, inner ball, far ball.
Mesh nested_parts() {
  Mesh m = merged(make_icosphere(1.0, 3), turned_inside_out(make_icosphere(0.6, 3)));
  m = merged(m, make_icosphere(0.3, 2));
  return merged(m, moved(make_icosphere(0.5, 2), {3, 0, 0}));
}

}  // namespace

TEST_CASE("triangle_components numbers the parts by their first triangle") {
  const Mesh one = make_icosphere(1.0, 1);
  const Mesh m = merged(merged(one, moved(one, {3, 0, 0})), moved(one, {6, 0, 0}));
  const std::vector<uint32_t> c = triangle_components(m);
  REQUIRE(c.size() == m.triangles.size());
  const size_t per = one.triangles.size();
  for (size_t t = 0; t < c.size(); ++t) CHECK(c[t] == t / per);
  CHECK(diagnose(m).components == 3);
}

TEST_CASE("a mesh's parts: separate balls are parts, a cavity belongs to the shell round it") {
  const Boundary boundary(nested_parts());
  const MeshParts parts(boundary);
  CHECK(parts.count() == 3);  // the shell (with its cavity), the inner ball, the far ball
  const uint32_t shell = parts.part_at({0.8, 0, 0}, 0.2);
  // Nearer the cavity than the outside: the cavity's surface is the nearest, still the shell's part.
  CHECK(parts.part_at({0, 0.65, 0}, 0.05) == shell);
  CHECK(parts.part_at({0, 0, -0.9}, 0.1) == shell);
  const uint32_t inner = parts.part_at({0, 0, 0}, 0.3), far = parts.part_at({3, 0, 0}, 0.5);
  CHECK(std::set<uint32_t>{shell, inner, far}.size() == 3);
  CHECK(parts.part_at({0.1, 0, 0}, 0.2) == inner);
  CHECK(parts.part_at({3.2, 0.1, 0}, 0.28) == far);
}

TEST_CASE("a hollow ball is one part") {
  const Boundary boundary(merged(make_icosphere(1.0, 3), turned_inside_out(make_icosphere(0.5, 3))));
  const MeshParts parts(boundary);
  CHECK(parts.count() == 1);
  CHECK(parts.part_at({0.75, 0, 0}, 0.25) == 0);
}

TEST_CASE("each part without a site gets its deepest candidate; a part too thin for one is counted") {
  const Mesh mesh = nested_parts();
  const Boundary boundary(mesh);
  const MeshParts parts(boundary);
  ProcessGroup one;
  const std::vector<BirthSite> sites{{{0, 0.8, 0}, 0.2}};  // in the shell only
  const HeldCandidates held = mesh_candidates(boundary, mesh.bounds(), 0.05, 0.1, BirthView{});
  const PartSiteChoice c = sites_for_empty_parts(parts, sites, held, 0.1, one);
  CHECK(c.counts.parts == 3);
  CHECK(c.counts.too_small == 0);
  REQUIRE(c.added.size() == 2);
  CHECK(c.counts.added == 2);
  // In part order, each the deepest candidate of its part (the lattice a step of 0.05).
  const uint32_t inner = parts.part_at({0, 0, 0}, 0.3), far = parts.part_at({3, 0, 0}, 0.5);
  CHECK(c.added[0].key == kPartKeyBase + inner);
  CHECK(c.added[1].key == kPartKeyBase + far);
  CHECK(length(c.added[0].site.position) < 0.05);
  CHECK(c.added[0].site.depth == doctest::Approx(0.3).epsilon(0.15));
  CHECK(length(c.added[1].site.position - Vec3(3, 0, 0)) < 0.05);
  CHECK(c.added[1].site.depth == doctest::Approx(0.5).epsilon(0.1));
  for (const LargeCandidate& q : held.points) {  // none deeper in its part
    const uint32_t p = parts.part_at(q.point, q.depth);
    if (p == inner) CHECK(q.depth <= c.added[0].site.depth);
    if (p == far) CHECK(q.depth <= c.added[1].site.depth);
  }
  // With sites needing 0.4 of depth the inner ball (0.3 deep) is too small.
  const PartSiteChoice thin = sites_for_empty_parts(parts, sites, held, 0.4, one);
  CHECK(thin.counts.too_small == 1);
  REQUIRE(thin.added.size() == 1);
  CHECK(thin.added[0].key == kPartKeyBase + far);
  // A site in every part: none added.
  const std::vector<BirthSite> everywhere{sites[0], {{0, 0, 0}, 0.3}, {{3, 0, 0}, 0.5}};
  CHECK(sites_for_empty_parts(parts, everywhere, held, 0.1, one).added.empty());
}
