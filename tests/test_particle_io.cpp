// Particle files: round trips of every format, atomic replacement, readers
// on hand-written, truncated and corrupted files, frame sequences, and the
// Khronos validator on our GLB files (where node and the validator exist).
#include <doctest/doctest.h>

#include "skip.hpp"
#include <tiny_gltf.h>
#include <assimp/Importer.hpp>
#include <assimp/scene.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <random>
#include <regex>

#include "particle_fixtures.hpp"
#include "pfill/atomic_file.hpp"
#include "pfill/error.hpp"
#include "pfill/particle_io.hpp"

using namespace pfill;
using pfill::test::ScratchDir;
namespace fs = std::filesystem;

namespace {

// PLY and GLB store floats: a value read back equals the float it was cast to.
void check_same_as_float(const ParticleSet& read, const ParticleSet& written, bool velocities) {
  REQUIRE(read.size() == written.size());
  for (size_t i = 0; i < written.size(); ++i) {
    for (int k = 0; k < 3; ++k) CHECK(read.positions[i][k] == double(float(written.positions[i][k])));
    CHECK(read.radii[i] == double(float(written.radii[i])));
    if (velocities)
      for (int k = 0; k < 3; ++k) CHECK(read.velocities[i][k] == double(float(written.velocities[i][k])));
  }
  CHECK(read.colours == written.colours);
  CHECK(read.has_velocities() == velocities);
}

float srgb_to_linear(uint8_t c) {
  const double s = c / 255.0;
  return float(s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4));
}

template <typename T>
std::vector<T> accessor_values(const tinygltf::Model& model, int index) {
  const tinygltf::Accessor& accessor = model.accessors.at(index);
  const tinygltf::BufferView& view = model.bufferViews.at(accessor.bufferView);
  const size_t components = accessor.type == TINYGLTF_TYPE_SCALAR ? 1 : accessor.type == TINYGLTF_TYPE_VEC3 ? 3 : 4;
  std::vector<T> values(accessor.count * components);
  std::memcpy(values.data(), model.buffers.at(view.buffer).data.data() + view.byteOffset + accessor.byteOffset,
              values.size() * sizeof(T));
  return values;
}

std::string error_message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// Reads VTP arrays by name, for both ascii and appended-raw encodings.
std::vector<double> vtp_array(const std::string& xml, const std::string& name) {
  const size_t at = xml.find("Name=\"" + name + "\"");
  REQUIRE(at != std::string::npos);
  const size_t tag_start = xml.rfind("<DataArray", at);
  const size_t tag_end = xml.find('>', at);
  const std::string tag = xml.substr(tag_start, tag_end - tag_start);
  std::smatch type_match;
  REQUIRE(std::regex_search(tag, type_match, std::regex("type=\"(\\w+)\"")));
  const std::string type = type_match[1];
  std::vector<double> values;
  std::smatch offset_match;
  if (std::regex_search(tag, offset_match, std::regex("offset=\"(\\d+)\""))) {
    const size_t data = xml.find('_', xml.find("<AppendedData")) + 1 + std::stoull(offset_match[1]);
    uint64_t bytes;
    std::memcpy(&bytes, xml.data() + data, 8);
    const char* p = xml.data() + data + 8;
    const size_t size = type == "UInt8" ? 1 : 8;
    for (size_t k = 0; k < bytes / size; ++k) {
      if (type == "Float64") { double v; std::memcpy(&v, p + 8 * k, 8); values.push_back(v); }
      else if (type == "Int64") { int64_t v; std::memcpy(&v, p + 8 * k, 8); values.push_back(double(v)); }
      else values.push_back(static_cast<unsigned char>(p[k]));
    }
  } else {
    std::istringstream text(xml.substr(tag_end + 1, xml.find("</DataArray>", tag_end) - tag_end - 1));
    double v;
    while (text >> v) values.push_back(v);
  }
  return values;
}

}  // namespace

TEST_CASE("validate rejects mismatched lengths, non-finite values and bad radii") {
  ParticleSet set = test::random_particles(5, 1, true, true);
  CHECK_NOTHROW(validate(set));
  ParticleSet bad = set;
  bad.radii.pop_back();
  CHECK_THROWS_AS(validate(bad), Error);
  bad = set;
  bad.colours.pop_back();
  CHECK_THROWS_AS(validate(bad), Error);
  bad = set;
  bad.positions[2].y = std::nan("");
  CHECK_THROWS_AS(validate(bad), Error);
  bad = set;
  bad.radii[3] = 0;
  CHECK(error_message_of([&] { validate(bad, "x.ply"); }).find("x.ply") != std::string::npos);
  bad = set;
  bad.velocities[0].z = INFINITY;
  CHECK_THROWS_AS(validate(bad), Error);
}

TEST_CASE("the format follows the extension") {
  CHECK(particle_format_from_path("a/b.PLY") == ParticleFormat::Ply);
  CHECK(particle_format_from_path("b.glb") == ParticleFormat::Glb);
  CHECK(particle_format_from_path("b.csv") == ParticleFormat::Csv);
  CHECK(particle_format_from_path("b.vtp") == ParticleFormat::Vtp);
  CHECK(error_message_of([] { particle_format_from_path("b.xyz"); }).find(".ply") != std::string::npos);
}

TEST_CASE("PLY round trip: binary little-endian, with and without colours and velocities") {
  ScratchDir dir("ply");
  for (int variant = 0; variant < 4; ++variant) {
    const bool colours = variant & 1, velocities = variant & 2;
    const ParticleSet set = test::random_particles(500, 10 + variant, colours, velocities);
    write_particles(set, dir / "p.ply");
    const std::string text = test::read_text(dir / "p.ply");
    CHECK(text.rfind("ply\nformat binary_little_endian 1.0\n", 0) == 0);
    CHECK(text.find("element vertex 500\n") != std::string::npos);
    CHECK((text.find("property uchar red") != std::string::npos) == colours);
    check_same_as_float(read_particles(dir / "p.ply"), set, velocities);
  }
  // Velocities stay out when not requested.
  const ParticleSet set = test::random_particles(10, 3, false, true);
  ParticleWriteOptions options;
  options.velocities = false;
  write_ply(set, dir / "q.ply", options);
  CHECK_FALSE(read_ply(dir / "q.ply").has_velocities());
}

TEST_CASE("our binary PLY is read by an independent reader (assimp) as the same points") {
  ScratchDir dir("plyassimp");
  const ParticleSet set = test::random_particles(100, 9, true, true);
  write_ply(set, dir / "p.ply");
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile((dir / "p.ply").string(), 0);
  REQUIRE_MESSAGE(scene != nullptr, importer.GetErrorString());
  REQUIRE(scene->mNumMeshes == 1);
  const aiMesh* mesh = scene->mMeshes[0];
  REQUIRE(mesh->mNumVertices == 100);
  for (unsigned i = 0; i < 100; ++i) {
    CHECK(mesh->mVertices[i].x == float(set.positions[i].x));
    CHECK(mesh->mVertices[i].z == float(set.positions[i].z));
  }
  if (mesh->HasVertexColors(0))
    CHECK(mesh->mColors[0][5].r == doctest::Approx(set.colours[5][0] / 255.0).epsilon(1e-3));
}

TEST_CASE("PLY reader: ascii, doubles, extra properties and elements, big-endian, default radius") {
  ScratchDir dir("plyread");
  test::write_text(dir / "a.ply",
                   "ply\r\nformat ascii 1.0\r\ncomment made by hand\r\n"
                   "element vertex 2\r\nproperty double x\r\nproperty double y\r\nproperty double z\r\n"
                   "property float nx\r\nproperty double radius\r\nproperty float red\r\n"
                   "property float green\r\nproperty float blue\r\nproperty list uchar int extra\r\n"
                   "element face 1\r\nproperty list uchar int vertex_indices\r\nend_header\r\n"
                   "0.125 -2 3e-1 0 0.5 1 0 0.5 2 7 8\r\n4 5 6 1 0.25 0 1 0 0\r\n3 0 1 1\r\n");
  ParticleSet a = read_ply(dir / "a.ply");
  REQUIRE(a.size() == 2);
  CHECK(a.positions[0] == Vec3(0.125, -2, 0.3));
  CHECK(a.radii[1] == 0.25);
  CHECK(a.colours[0] == Rgb8{255, 0, 128});
  CHECK(a.colours[1] == Rgb8{0, 255, 0});
  CHECK_FALSE(a.has_velocities());

  // A face element before the vertices is skipped, in binary too.
  std::string binary =
      "ply\nformat binary_big_endian 1.0\nelement face 1\nproperty list uchar int vertex_indices\n"
      "element vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  binary += std::string("\x01\x00\x00\x00\x05", 5);
  const float xyz[3] = {1.5f, -2.0f, 0.25f};
  for (float f : xyz) {
    unsigned char b[4];
    std::memcpy(b, &f, 4);
    binary += std::string{char(b[3]), char(b[2]), char(b[1]), char(b[0])};
  }
  test::write_text(dir / "b.ply", binary);
  CHECK(error_message_of([&] { read_ply(dir / "b.ply"); }).find("radius") != std::string::npos);
  ParticleReadOptions options;
  options.default_radius = 0.1;
  const ParticleSet b = read_ply(dir / "b.ply", options);
  REQUIRE(b.size() == 1);
  CHECK(b.positions[0] == Vec3(1.5, -2.0, 0.25));
  CHECK(b.radii[0] == 0.1);
}

TEST_CASE("PLY reader rejects malformed headers and short data with pfill::Error") {
  ScratchDir dir("plybad");
  const char* bad_files[] = {
      "",
      "not a ply file\n",
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n",  // no end_header
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "property float radius\nend_header\n1 2 3 0.1\n",  // 3 promised, 1 given
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
      "property float radius\nend_header\n1 2 zz 0.1\n",  // not a number
      "ply\nformat binary_little_endian 1.0\nelement vertex 99999999999\nproperty float x\n"
      "property float y\nproperty float z\nproperty float radius\nend_header\n0000",  // huge count
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n",
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
      "property float radius\nend_header\n1 2 3 -1\n",  // negative radius
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty quux x\nend_header\n1\n",
  };
  for (const char* text : bad_files) {
    CAPTURE(text);
    test::write_text(dir / "bad.ply", text);
    CHECK_THROWS_AS(read_ply(dir / "bad.ply"), Error);
  }
  CHECK_THROWS_AS(read_ply(dir / "missing.ply"), Error);
  CHECK_THROWS_AS(read_particles(dir.path() / "x.glb"), Error);  // we do not read GLB
}

TEST_CASE("CSV round trip is exact, and the reader follows the header") {
  ScratchDir dir("csv");
  for (int variant = 0; variant < 4; ++variant) {
    const bool colours = variant & 1, velocities = variant & 2;
    const ParticleSet set = test::random_particles(300, 20 + variant, colours, velocities);
    write_particles(set, dir / "p.csv");
    const std::string text = test::read_text(dir / "p.csv");
    std::string header = "x,y,z,radius";
    if (colours) header += ",r,g,b";
    if (velocities) header += ",vx,vy,vz";
    header += ",id";  // 1..N: the set has no ids
    CHECK(text.rfind(header + "\n", 0) == 0);
    const ParticleSet read = read_particles(dir / "p.csv");
    CHECK(read.positions == set.positions);
    CHECK(read.radii == set.radii);
    CHECK(read.colours == set.colours);
    CHECK(read.velocities == set.velocities);
  }
  test::write_text(dir / "h.csv", "id, Z ,Y, X,red,green,blue\n7,3,2,1,0,128,255\n\n8,6,5,4,1,2,3\n");
  CHECK_THROWS_AS(read_csv(dir / "h.csv"), Error);  // no radius
  ParticleReadOptions options;
  options.default_radius = 0.5;
  const ParticleSet h = read_csv(dir / "h.csv", options);
  REQUIRE(h.size() == 2);
  CHECK(h.positions[0] == Vec3(1, 2, 3));
  CHECK(h.positions[1] == Vec3(4, 5, 6));
  CHECK(h.colours[0] == Rgb8{0, 128, 255});
  CHECK(h.radii[1] == 0.5);
  test::write_text(dir / "bad.csv", "x,y,z,radius\n1,2,3,0.1\n1,2,three,0.1\n");
  CHECK(error_message_of([&] { read_csv(dir / "bad.csv"); }).find("line 3") != std::string::npos);
  test::write_text(dir / "short.csv", "x,y,z,radius\n1,2,3\n");
  CHECK_THROWS_AS(read_csv(dir / "short.csv"), Error);
}

TEST_CASE("VTP: ascii and appended binary hold the same particles") {
  ScratchDir dir("vtp");
  const ParticleSet set = test::random_particles(50, 5, true, true);
  for (bool binary : {false, true}) {
    ParticleWriteOptions options;
    options.vtp_binary = binary;
    write_particles(set, dir / "p.vtp", options);
    const std::string xml = test::read_text(dir / "p.vtp");
    CHECK(xml.find("NumberOfPoints=\"50\"") != std::string::npos);
    const std::vector<double> points = vtp_array(xml, "Points"), radius = vtp_array(xml, "radius"),
                              colour = vtp_array(xml, "colour"), velocity = vtp_array(xml, "velocity"),
                              offsets = vtp_array(xml, "offsets");
    REQUIRE(points.size() == 150);
    REQUIRE(radius.size() == 50);
    REQUIRE(colour.size() == 150);
    REQUIRE(velocity.size() == 150);
    REQUIRE(offsets.size() == 50);
    CHECK(offsets.back() == 50);
    for (size_t i = 0; i < 50; ++i) {
      CHECK(radius[i] == set.radii[i]);
      for (int k = 0; k < 3; ++k) {
        CHECK(points[3 * i + k] == set.positions[i][k]);
        CHECK(velocity[3 * i + k] == set.velocities[i][k]);
        CHECK(colour[3 * i + k] == set.colours[i][k]);
      }
    }
  }
}

TEST_CASE("GLB read back by tinygltf: POINTS with POSITION bounds, linear COLOR_0, _RADIUS, instanced spheres") {
  ScratchDir dir("glb");
  const ParticleSet set = test::random_particles(200, 7, true, false);
  ParticleWriteOptions options;
  options.spheres = true;
  write_particles(set, dir / "p.glb", options);

  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string error, warning;
  REQUIRE(loader.LoadBinaryFromFile(&model, &error, &warning, (dir / "p.glb").string()));
  REQUIRE(model.meshes.size() == 2);
  const tinygltf::Primitive& points = model.meshes[0].primitives.at(0);
  CHECK(points.mode == TINYGLTF_MODE_POINTS);
  const tinygltf::Accessor& position = model.accessors.at(points.attributes.at("POSITION"));
  const std::vector<float> xyz = accessor_values<float>(model, points.attributes.at("POSITION"));
  const std::vector<float> radius = accessor_values<float>(model, points.attributes.at("_RADIUS"));
  const std::vector<float> colour = accessor_values<float>(model, points.attributes.at("COLOR_0"));
  REQUIRE(xyz.size() == 600);
  REQUIRE(radius.size() == 200);
  REQUIRE(colour.size() == 600);
  REQUIRE(position.minValues.size() == 3);
  for (int k = 0; k < 3; ++k) {
    float lo = INFINITY, hi = -INFINITY;
    for (size_t i = 0; i < 200; ++i) {
      CHECK(xyz[3 * i + k] == float(set.positions[i][k]));
      CHECK(colour[3 * i + k] == doctest::Approx(srgb_to_linear(set.colours[i][k])));
      lo = std::min(lo, float(set.positions[i][k]));
      hi = std::max(hi, float(set.positions[i][k]));
    }
    CHECK(position.minValues[k] == lo);
    CHECK(position.maxValues[k] == hi);
  }
  for (size_t i = 0; i < 200; ++i) CHECK(radius[i] == float(set.radii[i]));

  // Spheres: EXT_mesh_gpu_instancing used but not required.
  const tinygltf::Node& spheres = model.nodes.at(1);
  REQUIRE(spheres.extensions.count("EXT_mesh_gpu_instancing") == 1);
  const tinygltf::Value& attributes = spheres.extensions.at("EXT_mesh_gpu_instancing").Get("attributes");
  const std::vector<float> translation =
      accessor_values<float>(model, attributes.Get("TRANSLATION").Get<int>());
  const std::vector<float> scale = accessor_values<float>(model, attributes.Get("SCALE").Get<int>());
  CHECK(translation == xyz);
  double mean = 0;
  for (double r : set.radii) mean += r / 200;
  const std::vector<float> sphere = accessor_values<float>(
      model, model.meshes[1].primitives.at(0).attributes.at("POSITION"));
  const double base_radius = std::sqrt(sphere[0] * sphere[0] + sphere[1] * sphere[1] + sphere[2] * sphere[2]);
  CHECK(base_radius == doctest::Approx(mean).epsilon(1e-5));
  CHECK(scale[3 * 17] * base_radius == doctest::Approx(set.radii[17]).epsilon(1e-5));
  CHECK(std::count(model.extensionsUsed.begin(), model.extensionsUsed.end(), "EXT_mesh_gpu_instancing") == 1);
  CHECK(model.extensionsRequired.empty());
}

TEST_CASE("GLB files pass the Khronos glTF validator with no errors (skipped without node)") {
  const fs::path script = fs::path(__FILE__).parent_path().parent_path() / "scripts" / "validate_gltf.js";
  if (!fs::exists(script) || std::system("node --version > /dev/null 2>&1") != 0) {
    PFILL_SKIP("node or scripts/validate_gltf.js missing: the validator test cannot run");
    return;
  }
  ScratchDir dir("gltfval");
  struct Case { const char* name; bool colours; bool spheres; size_t n; };
  for (const Case& c : {Case{"plain.glb", false, false, 100}, Case{"colours.glb", true, false, 100},
                        Case{"spheres.glb", true, true, 100}, Case{"empty.glb", false, true, 0}}) {
    CAPTURE(c.name);
    ParticleWriteOptions options;
    options.spheres = c.spheres;
    write_glb(test::random_particles(c.n, 3, c.colours, false), dir / c.name, options);
    const fs::path report = dir / (std::string(c.name) + ".json");
    const int status = std::system(("node '" + script.string() + "' '" + (dir / c.name).string() + "' > '" +
                                    report.string() + "' 2>/dev/null").c_str());
    if (WIFEXITED(status) && WEXITSTATUS(status) == 2) {
      PFILL_SKIP("gltf-validator not installed (npm install -g gltf-validator)");
      return;
    }
    const std::string text = test::read_text(report);
    CAPTURE(text);
    CHECK(text.find("\"numErrors\": 0") != std::string::npos);
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 0);
  }
}

TEST_CASE("writes are atomic: missing folder, failing writer, old file kept until the new one is complete") {
  ScratchDir dir("atomic");
  const ParticleSet set = test::random_particles(20, 1, false, false);

  for (const char* name : {"p.ply", "p.glb", "p.csv", "p.vtp"}) {
    CAPTURE(name);
    const fs::path missing = dir.path() / "no_such_folder" / name;
    const std::string message = error_message_of([&] { write_particles(set, missing); });
    CHECK(message.find("no_such_folder") != std::string::npos);
    CHECK(message.find("does not exist") != std::string::npos);
    CHECK_FALSE(fs::exists(missing));

    // An invalid set fails before any byte changes; the old file stays.
    test::write_text(dir / name, "old content");
    ParticleSet bad = set;
    bad.radii[4] = -1;
    CHECK_THROWS_AS(write_particles(bad, dir / name), Error);
    CHECK(test::read_text(dir / name) == "old content");
  }
  CHECK(dir.file_count() == 4);  // no temporary files left behind

  // A writer that fails half way: the target keeps its old content, the
  // temporary file is gone; while writing, the target is still the old file.
  test::write_text(dir / "w.txt", "old content");
  CHECK_THROWS_AS(write_file_atomically(dir / "w.txt",
                                        [&](AtomicFile& file) {
                                          file.write("new half");
                                          CHECK(test::read_text(dir / "w.txt") == "old content");
                                          throw Error("simulated failure");
                                        }),
                  Error);
  CHECK(test::read_text(dir / "w.txt") == "old content");
  CHECK(dir.file_count() == 5);
  write_file_atomically(dir / "w.txt", [](AtomicFile& file) { file.write("new content"); });
  CHECK(test::read_text(dir / "w.txt") == "new content");
  CHECK(dir.file_count() == 5);

  // A folder the process cannot create files in (true even for root).
  const std::string message = error_message_of([&] { write_particles(set, "/proc/pfill_test.ply"); });
  CHECK(message.find("/proc/pfill_test.ply") != std::string::npos);
  CHECK_THROWS_AS(write_particles(set, dir.path()), Error);  // a folder, not a file
}

TEST_CASE("readers on truncated and corrupted files give a valid set or pfill::Error, never a crash") {
  ScratchDir dir("fuzz");
  const ParticleSet set = test::random_particles(64, 11, true, true);
  write_particles(set, dir / "good.ply");
  write_particles(set, dir / "good.csv");
  ParticleSet ascii_set = set;
  std::mt19937 rng(12345);  // fixed seed: the same corruptions every run
  int errors = 0, valid = 0;
  for (const char* name : {"good.ply", "good.csv"}) {
    const std::string original = test::read_text(dir / name);
    const std::string extension = fs::path(name).extension().string();
    for (int trial = 0; trial < 150; ++trial) {
      std::string bytes = original;
      if (trial % 2 == 0) {
        bytes.resize(std::uniform_int_distribution<size_t>(0, bytes.size() - 1)(rng));
      } else {
        const int flips = 1 + trial % 7;
        for (int f = 0; f < flips; ++f)
          bytes[std::uniform_int_distribution<size_t>(0, bytes.size() - 1)(rng)] =
              static_cast<char>(std::uniform_int_distribution<int>(0, 255)(rng));
      }
      const fs::path corrupted = dir / ("c" + extension);
      test::write_text(corrupted, bytes);
      try {
        const ParticleSet read = read_particles(corrupted);
        CHECK_NOTHROW(validate(read));
        ++valid;
      } catch (const Error&) {
        ++errors;
      }
    }
  }
  CHECK(errors > 0);
  CHECK(valid + errors == 300);
}

TEST_CASE("FrameWriter writes numbered PLY frames every K steps into a new folder") {
  ScratchDir dir("frames");
  const fs::path frames = dir.path() / "nested" / "frames";
  FrameWriter writer(frames, 5);
  for (uint64_t step = 0; step <= 12; ++step) {
    ParticleSet set = test::random_particles(step + 1, uint32_t(step), false, false);
    writer.offer(step, set);
  }
  CHECK(writer.frames_written() == 3);  // steps 0, 5, 10
  const fs::path last = writer.write(test::random_particles(4, 1, false, false));
  CHECK(last.filename() == "frame_000003.ply");
  const std::vector<fs::path> listed = list_frames(frames);
  REQUIRE(listed.size() == 4);
  CHECK(listed[0].filename() == "frame_000000.ply");
  CHECK(listed[2].filename() == "frame_000002.ply");
  CHECK(read_ply(listed[1]).size() == 6);   // step 5
  CHECK(read_ply(listed[2]).size() == 11);  // step 10
  CHECK_THROWS_AS(FrameWriter(frames, 0), Error);
  CHECK_THROWS_AS(list_frames(dir.path() / "none"), Error);
}
