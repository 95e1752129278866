// The formats for simulation codes and other tools: LAMMPS data (.data),
// Yade text (.xyzr), Houdini attribute names, ids in every format, and
// velocities in every format that has a place for them. (LAMMPS itself
// reads the .data file in tests/lammps_read_data.sh where it is installed.)
#include <doctest/doctest.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cstring>
#include <map>
#include <sstream>

#include "particle_fixtures.hpp"
#include "pfill/error.hpp"
#include "pfill/particle_io.hpp"

using namespace pfill;
using pfill::test::ScratchDir;
namespace fs = std::filesystem;

namespace {

// Ids that are not 1..N in file order, as a fill's are after removals and sorts.
ParticleSet particles_with_ids(size_t n, uint32_t seed, bool colours, bool velocities) {
  ParticleSet set = test::random_particles(n, seed, colours, velocities);
  for (size_t i = 0; i < n; ++i) set.ids.push_back(1000 + 7 * (n - i));
  return set;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::vector<double> numbers_of(const std::string& line) {
  std::istringstream in(line);
  std::vector<double> v;
  for (double x; in >> x;) v.push_back(x);
  return v;
}

}  // namespace

TEST_CASE("the new formats follow the extension; attribute names parse") {
  CHECK(particle_format_from_path("a/fill.data") == ParticleFormat::LammpsData);
  CHECK(particle_format_from_path("fill.XYZR") == ParticleFormat::Xyzr);
  CHECK(parse_attribute_names("houdini") == AttributeNames::Houdini);
  CHECK(parse_attribute_names("pfill") == AttributeNames::Pfill);
  CHECK_THROWS_AS(parse_attribute_names("maya"), Error);
}

TEST_CASE("LAMMPS data: atom_style sphere lines with the ids, diameters, density and positions; the box holds the mesh and every sphere") {
  ScratchDir dir("lammps");
  const ParticleSet set = particles_with_ids(50, 3, true, true);
  ParticleWriteOptions options;
  options.density = 2.5;
  options.box.add(Vec3(-3, -2, -1));
  options.box.add(Vec3(0.5, 0.5, 0.5));  // smaller than the particles in +x,+y,+z
  write_particles(set, dir / "p.data", options);
  const std::vector<std::string> lines = lines_of(test::read_text(dir / "p.data"));
  REQUIRE(lines.size() > 10);
  CHECK(std::find(lines.begin(), lines.end(), "50 atoms") != lines.end());
  CHECK(std::find(lines.begin(), lines.end(), "1 atom types") != lines.end());
  Box3 box;
  for (const std::string& line : lines) {
    const std::vector<double> v = numbers_of(line);
    if (line.find("xlo xhi") != std::string::npos) box.lo.x = v[0], box.hi.x = v[1];
    if (line.find("ylo yhi") != std::string::npos) box.lo.y = v[0], box.hi.y = v[1];
    if (line.find("zlo zhi") != std::string::npos) box.lo.z = v[0], box.hi.z = v[1];
  }
  CHECK(box.lo.x < -3);
  CHECK(box.lo.y < -2);
  const auto atoms = std::find(lines.begin(), lines.end(), "Atoms # sphere");
  REQUIRE(atoms != lines.end());
  for (size_t i = 0; i < set.size(); ++i) {
    const std::vector<double> v = numbers_of(*(atoms + 2 + static_cast<long>(i)));
    REQUIRE(v.size() == 7);
    CHECK(v[0] == double(set.ids[i]));
    CHECK(v[1] == 1);
    CHECK(v[2] == 2 * set.radii[i]);
    CHECK(v[3] == 2.5);
    for (int k = 0; k < 3; ++k) {
      CHECK(v[4 + k] == set.positions[i][k]);
      CHECK(v[4 + k] - set.radii[i] > box.lo[k]);
      CHECK(v[4 + k] + set.radii[i] < box.hi[k]);
    }
  }
  const auto velocities = std::find(lines.begin(), lines.end(), "Velocities");
  REQUIRE(velocities != lines.end());
  const std::vector<double> v = numbers_of(*(velocities + 2));
  REQUIRE(v.size() == 7);
  CHECK(v[0] == double(set.ids[0]));
  CHECK(v[1] == set.velocities[0].x);
  CHECK(v[6] == 0);

  options.velocities = false;
  write_particles(set, dir / "q.data", options);
  CHECK(test::read_text(dir / "q.data").find("Velocities") == std::string::npos);
  options.density = 0;
  CHECK_THROWS_AS(write_particles(set, dir / "r.data", options), Error);
  CHECK_FALSE(fs::exists(dir / "r.data"));
}

TEST_CASE("xyzr: comment lines, then x y z r id [vx vy vz] per particle, no blank line (Yade's ymport.text)") {
  ScratchDir dir("xyzr");
  const ParticleSet set = particles_with_ids(40, 4, true, true);
  write_particles(set, dir / "p.xyzr");
  std::vector<std::string> lines = lines_of(test::read_text(dir / "p.xyzr"));
  size_t comments = 0;
  while (comments < lines.size() && lines[comments].rfind("#", 0) == 0) {
    CHECK(lines[comments].rfind("#format", 0) != 0);  // ymport.text would take it as a format
    ++comments;
  }
  REQUIRE(lines.size() == comments + set.size());
  for (size_t i = 0; i < set.size(); ++i) {
    const std::vector<double> v = numbers_of(lines[comments + i]);
    REQUIRE(v.size() == 8);
    for (int k = 0; k < 3; ++k) CHECK(v[k] == set.positions[i][k]);
    CHECK(v[3] == set.radii[i]);
    CHECK(v[4] == double(set.ids[i]));
    CHECK(v[5] == set.velocities[i].x);
  }
  ParticleWriteOptions options;
  options.velocities = false;
  write_particles(set, dir / "q.xyzr", options);
  lines = lines_of(test::read_text(dir / "q.xyzr"));
  CHECK(numbers_of(lines.back()).size() == 5);
}

TEST_CASE("ids: PLY and CSV give them back; VTP and GLB carry them; a set without ids is numbered 1..N") {
  ScratchDir dir("ids");
  const ParticleSet set = particles_with_ids(30, 5, true, false);
  for (const char* name : {"p.ply", "p.csv"}) {
    write_particles(set, dir / name);
    CHECK(read_particles(dir / name).ids == set.ids);
  }
  ParticleSet plain = set;
  plain.ids.clear();
  write_particles(plain, dir / "n.csv");
  const ParticleSet numbered = read_particles(dir / "n.csv");
  REQUIRE(numbered.ids.size() == 30);
  CHECK(numbered.ids.front() == 1);
  CHECK(numbered.ids.back() == 30);

  write_particles(set, dir / "p.vtp");
  const std::string vtp = test::read_text(dir / "p.vtp");
  CHECK(vtp.find("type=\"Int64\" Name=\"id\"") != std::string::npos);

  write_particles(set, dir / "p.glb");
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string error, warning;
  REQUIRE(loader.LoadBinaryFromFile(&model, &error, &warning, (dir / "p.glb").string()));
  const auto& attributes = model.meshes.at(0).primitives.at(0).attributes;
  REQUIRE(attributes.count("_ID") == 1);
  const tinygltf::Accessor& accessor = model.accessors.at(attributes.at("_ID"));
  const tinygltf::BufferView& view = model.bufferViews.at(accessor.bufferView);
  std::vector<float> ids(accessor.count);
  std::memcpy(ids.data(), model.buffers[0].data.data() + view.byteOffset + accessor.byteOffset, ids.size() * 4);
  for (size_t i = 0; i < set.size(); ++i) CHECK(ids[i] == float(set.ids[i]));
  CHECK(attributes.count("_VELOCITY") == 0);
}

TEST_CASE("velocities in every format that has a place for them, only when asked") {
  ScratchDir dir("velocities");
  const ParticleSet set = particles_with_ids(20, 6, false, true);
  for (const char* name : {"p.ply", "p.csv"}) {
    write_particles(set, dir / name);
    const ParticleSet back = read_particles(dir / name);
    REQUIRE(back.has_velocities());
    CHECK(back.velocities[3].y == (std::string(name) == "p.csv" ? set.velocities[3].y : double(float(set.velocities[3].y))));
  }
  write_particles(set, dir / "p.vtp");
  CHECK(test::read_text(dir / "p.vtp").find("Name=\"velocity\"") != std::string::npos);
  write_particles(set, dir / "p.glb");
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string error, warning;
  REQUIRE(loader.LoadBinaryFromFile(&model, &error, &warning, (dir / "p.glb").string()));
  CHECK(model.meshes.at(0).primitives.at(0).attributes.count("_VELOCITY") == 1);

  ParticleWriteOptions off;
  off.velocities = false;
  for (const char* name : {"q.ply", "q.csv", "q.vtp", "q.glb", "q.data", "q.xyzr"}) {
    write_particles(set, dir / name, off);
    const std::string text = test::read_text(dir / name);
    INFO(name);
    CHECK(text.find("vx") == std::string::npos);
    CHECK(text.find("velocity") == std::string::npos);
    CHECK(text.find("VELOCITY") == std::string::npos);
    CHECK(text.find("Velocities") == std::string::npos);
  }
}

TEST_CASE("Houdini names: pscale, Cd as floats 0..1, v, id in PLY and CSV; pfill reads them back the same") {
  ScratchDir dir("houdini");
  const ParticleSet set = particles_with_ids(25, 7, true, true);
  ParticleWriteOptions options;
  options.names = AttributeNames::Houdini;
  write_particles(set, dir / "h.ply", options);
  const std::string ply = test::read_text(dir / "h.ply");
  for (const char* property : {"property float pscale\n", "property float Cd.r\n", "property float Cd.b\n",
                               "property float v.x\n", "property uint id\n"})
    CHECK(ply.find(property) != std::string::npos);
  CHECK(ply.find("property float radius") == std::string::npos);
  CHECK(ply.find("property uchar red") == std::string::npos);

  write_particles(set, dir / "h.csv", options);
  const std::vector<std::string> lines = lines_of(test::read_text(dir / "h.csv"));
  CHECK(lines[0] == "x,y,z,pscale,Cd.r,Cd.g,Cd.b,v.x,v.y,v.z,id");
  std::vector<std::string> fields;
  std::istringstream row(lines[1]);
  for (std::string f; std::getline(row, f, ',');) fields.push_back(f);
  REQUIRE(fields.size() == 11);
  CHECK(std::stod(fields[4]) == doctest::Approx(set.colours[0][0] / 255.0));
  CHECK(std::stod(fields[4]) <= 1.0);

  for (const char* name : {"h.ply", "h.csv"}) {
    INFO(name);
    const ParticleSet back = read_particles(dir / name);
    CHECK(back.colours == set.colours);
    CHECK(back.ids == set.ids);
    REQUIRE(back.size() == set.size());
    CHECK(back.radii[4] == doctest::Approx(set.radii[4]));
    CHECK(back.velocities[4].z == doctest::Approx(set.velocities[4].z));
  }
}

TEST_CASE("frames carry the ids and, when asked, the velocities") {
  ScratchDir dir("frames_ids");
  const ParticleSet set = particles_with_ids(10, 8, false, true);
  ParticleWriteOptions options;
  options.velocities = false;
  FrameWriter frames(dir / "frames", 1, options);
  frames.write(set);
  const ParticleSet back = read_particles(FrameWriter::frame_path(dir / "frames", 0));
  CHECK(back.ids == set.ids);
  CHECK_FALSE(back.has_velocities());
}
