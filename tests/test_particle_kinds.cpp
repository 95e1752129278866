// The boundary particles' attributes (kind, normal, area) read back from
// every format that writes them (ParticleReadOptions::attributes): what
// `pfill check --shell`, `pfill contacts` and Python's read_particles use.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "pfill/error.hpp"
#include "pfill/particle_io.hpp"

using namespace pfill;
namespace fs = std::filesystem;

namespace {

fs::path temp_path(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("pfill_kinds_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir / name;
}

// Three inner spheres and two boundary particles, as fill --shell joins them.
void shell_set(ParticleSet& p, ParticleAttributes& a) {
  p.positions = {{0, 0, 0}, {0.5, 0, 0}, {0, 0.5, 0}, {1, 0, 0}, {0, 1, 0}};
  p.radii = {0.2, 0.2, 0.2, 0.1, 0.1};
  a.kinds = {0, 0, 0, 1, 1};
  a.normals = {{}, {}, {}, {1, 0, 0}, {0, 0.6, 0.8}};
  a.areas = {0, 0, 0, 0.25, 0.125};
}

}  // namespace

TEST_CASE("particle kinds: written and read back with the normals and areas, format by format") {
  ParticleSet p;
  ParticleAttributes a;
  shell_set(p, a);
  for (const char* name : {"k.ply", "k.csv", "k.vtp", "k.glb", "k.xyzr"}) {
    for (bool binary : {true, false}) {
      if (!binary && std::string(name) != "k.vtp") continue;  // VTP: ascii too
      CAPTURE(name);
      CAPTURE(binary);
      const fs::path path = temp_path(name);
      ParticleWriteOptions wo;
      wo.attributes = &a;
      wo.vtp_binary = binary;
      write_particles(p, path, wo);
      ParticleAttributes back;
      back.kinds = {7};  // replaced, not appended to
      ParticleReadOptions ro;
      ro.attributes = &back;
      const ParticleSet q = read_particles(path, ro);
      REQUIRE(q.size() == p.size());
      CHECK(back.kinds == a.kinds);
      REQUIRE(back.normals.size() == a.normals.size());
      REQUIRE(back.areas.size() == a.areas.size());
      for (size_t i = 0; i < p.size(); ++i) {
        CHECK(length(back.normals[i] - a.normals[i]) < 1e-6);
        CHECK(back.areas[i] == doctest::Approx(a.areas[i]));
      }
      // Without a place for them the read is as before.
      CHECK(read_particles(path).size() == p.size());
    }
  }
}

TEST_CASE("particle kinds: a file without them gives empty vectors; a kind other than 0 or 1 is refused") {
  ParticleSet p;
  ParticleAttributes a;
  shell_set(p, a);
  const fs::path plain = temp_path("plain.ply");
  write_particles(p, plain);
  ParticleAttributes back;
  back.kinds = {1};
  ParticleReadOptions ro;
  ro.attributes = &back;
  read_particles(plain, ro);
  CHECK(!back.has_kinds());
  CHECK(!back.has_normals());
  CHECK(!back.has_areas());

  const fs::path data = temp_path("k.data");
  ParticleWriteOptions wo;
  wo.attributes = &a;
  write_particles(p, data, wo);
  read_particles(data, ro);  // LAMMPS: atom types, not kinds
  CHECK(!back.has_kinds());

  const fs::path bad = temp_path("bad.csv");
  std::ofstream(bad) << "x,y,z,radius,kind\n0,0,0,1,0\n1,0,0,1,2\n";
  CHECK_THROWS_AS(read_particles(bad, ro), Error);
  CHECK(read_particles(bad).size() == 2);  // kinds not asked for: not read
}
