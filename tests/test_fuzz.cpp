// Seeded corruption fuzzing of every mesh loader and particle reader, a
// fixed number of inputs per target (or PFILL_FUZZ_SECONDS each): truncations,
// flipped and random bytes, chunks deleted or repeated, and numbers that
// break parsers (nan, 1e300, 1.9e18, 4294967295, ...) put into valid files.
// Every input must give a valid result or one pfill::Error, never a crash or
// a hang. A loaded mesh also goes through diagnose() and Boundary (Embree),
// a particle set through validate(). The input being tried is written to
// fuzz_current/ first, so a crash leaves it behind to be kept as a
// regression file in tests/fuzz_regressions/, which the last test replays.
#include <doctest/doctest.h>

#include <sys/stat.h>

#include <chrono>
#include <fstream>
#include <map>
#include <sstream>
#include <cstdlib>
#include <filesystem>
#include <random>

#include "mesh_writers.hpp"
#include "particle_fixtures.hpp"
#include "pfill/boundary.hpp"
#include "pfill/error.hpp"
#include "pfill/mesh_diagnostics.hpp"
#include "pfill/mesh_io.hpp"
#include "pfill/particle_io.hpp"
#include "pfill/shapes.hpp"

namespace fs = std::filesystem;
using namespace pfill;

namespace {

// CI tries the same inputs on every run: the first kFuzzInputs of each
// target's seeded sequence (within a time cap, should a machine crawl), so
// a green run stays green. PFILL_FUZZ_SECONDS=S fuzzes each target for S
// seconds instead, going as far down the sequence as that allows.
constexpr size_t kFuzzInputs = 1000;
constexpr double kFuzzCapSeconds = 30;

struct FuzzBudget {
  size_t inputs;
  double seconds;
};

FuzzBudget fuzz_budget() {
  const char* text = std::getenv("PFILL_FUZZ_SECONDS");
  const double s = text ? std::atof(text) : 0;
  if (s > 0) return {SIZE_MAX, s};
  return {kFuzzInputs, kFuzzCapSeconds};
}

// One corruption of `bytes`, chosen and placed by `random`.
std::vector<uint8_t> mutate(std::vector<uint8_t> bytes, std::mt19937_64& random) {
  static const char* const kNumbers[] = {"nan", "-inf", "1e300", "1.9e18", "-2e18", "4294967295", "-1",
                                         "99999999999999999999", "0/881192", "1e-320", "0x7fffffff", "-0"};
  auto at = [&](size_t size) { return size ? std::uniform_int_distribution<size_t>(0, size - 1)(random) : 0; };
  const int rounds = 1 + static_cast<int>(random() % 3);
  for (int round = 0; round < rounds && !bytes.empty(); ++round) {
    switch (random() % 7) {
      case 0: bytes.resize(at(bytes.size())); break;  // cut short
      case 1: bytes[at(bytes.size())] ^= static_cast<uint8_t>(1u << (random() % 8)); break;
      case 2:
        for (int k = 0, n = 1 + static_cast<int>(random() % 16); k < n; ++k)
          bytes[at(bytes.size())] = static_cast<uint8_t>(random());
        break;
      case 3: {  // a chunk deleted
        const size_t from = at(bytes.size());
        const size_t length = std::min(bytes.size() - from, static_cast<size_t>(1 + random() % 64));
        bytes.erase(bytes.begin() + static_cast<long>(from), bytes.begin() + static_cast<long>(from + length));
        break;
      }
      case 4: {  // a chunk repeated
        const size_t from = at(bytes.size());
        const size_t length = std::min(bytes.size() - from, static_cast<size_t>(1 + random() % 64));
        const std::vector<uint8_t> chunk(bytes.begin() + static_cast<long>(from),
                                         bytes.begin() + static_cast<long>(from + length));
        bytes.insert(bytes.begin() + static_cast<long>(at(bytes.size())), chunk.begin(), chunk.end());
        break;
      }
      case 5: {  // a number that breaks parsers, over a token
        const std::string number = kNumbers[random() % (sizeof kNumbers / sizeof *kNumbers)];
        const size_t from = at(bytes.size());
        size_t end = from;
        while (end < bytes.size() && bytes[end] != ' ' && bytes[end] != '\n' && bytes[end] != ',') ++end;
        bytes.erase(bytes.begin() + static_cast<long>(from), bytes.begin() + static_cast<long>(end));
        bytes.insert(bytes.begin() + static_cast<long>(from), number.begin(), number.end());
        break;
      }
      default: {  // a binary word set to an extreme
        const size_t from = at(bytes.size() >= 4 ? bytes.size() - 3 : 0);
        const uint32_t words[] = {0xFFFFFFFFu, 0x7F800000u /* inf */, 0x7FC00000u /* nan */, 0x5DD3E8A0u /* ~1.9e18 */,
                                  0x80000000u};
        const uint32_t w = words[random() % 5];
        for (int k = 0; k < 4 && from + k < bytes.size(); ++k) bytes[from + k] = static_cast<uint8_t>(w >> (8 * k));
      }
    }
  }
  return bytes;
}

// What a reader did with one input.
enum class Outcome { Valid, Rejected };

Outcome try_mesh(const std::string& path) {
  try {
    const Mesh m = load_mesh(path);
    validate(m);
    const MeshDiagnostics d = diagnose(m);
    CHECK(d.triangles == m.triangle_count());
    if (m.triangle_count() <= 20000) {
      const Boundary b(m);
      const Vec3 c = m.bounds().centre();
      (void)b.inside(c);
      (void)b.signed_distance(c + m.bounds().size() * 0.37);
    }
    return Outcome::Valid;
  } catch (const Error& e) {
    const std::string message = e.what();
    CHECK(message.size() <= 700);
    CHECK(message.find_first_of(std::string("\n\r\x1b\0", 4)) == std::string::npos);
    return Outcome::Rejected;
  }
}

Outcome try_particles(const std::string& path) {
  try {
    const ParticleSet s = read_particles(path);
    validate(s, path);
    (void)s.bounds();
    return Outcome::Valid;
  } catch (const Error& e) {
    const std::string message = e.what();
    CHECK(message.size() <= 700);
    CHECK(message.find_first_of(std::string("\n\r\x1b\0", 4)) == std::string::npos);
    return Outcome::Rejected;
  }
}

fs::path current_folder() {
  const fs::path folder = fs::current_path() / "fuzz_current";
  fs::create_directories(folder);
  return folder;
}

// Fuzzes one target for fuzz_budget(): `seed_file` is the valid input the
// corruptions start from, `extension` that of the file each is tried as.
void fuzz(const std::string& target, const std::string& seed_file, const std::string& extension,
          Outcome (*read)(const std::string&)) {
  const std::vector<uint8_t> original = test::read_bytes(seed_file);
  REQUIRE(original.size() > 8);
  REQUIRE(read(seed_file) == Outcome::Valid);
  std::string file = target + "." + extension;  // one name per target: the tests run side by side
  for (char& c : file) if (c == ' ') c = '_';
  const fs::path input = current_folder() / file;
  MESSAGE("fuzzing " << target << "; a crash leaves its input in " << input.string());
  std::mt19937_64 random(std::hash<std::string>()(target) ^ 20261202u);
  size_t tried = 0, valid = 0;
  const auto start = std::chrono::steady_clock::now();
  const FuzzBudget budget = fuzz_budget();
  while (tried < budget.inputs &&
         std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < budget.seconds) {
    test::write_bytes(input.string(), mutate(original, random));
    valid += read(input.string()) == Outcome::Valid;
    ++tried;
  }
  fs::remove(input);
  MESSAGE(target << ": " << tried << " inputs tried, " << valid << " valid, " << tried - valid << " rejected");
  CHECK(tried > 10);
}

struct Seeds {
  test::TempDir dir{"fuzzseeds"};
  Mesh mesh = make_torus(1.0, 0.4, 16, 8);
  std::string file(const std::string& name) const { return dir.file(name); }
};

}  // namespace

TEST_CASE("fuzz: OBJ loader") {
  Seeds s;
  test::write_obj(s.mesh, s.file("seed.obj"));
  fuzz("obj", s.file("seed.obj"), "obj", try_mesh);
}
TEST_CASE("fuzz: STL loader, ascii and binary") {
  Seeds s;
  test::write_stl_ascii(s.mesh, s.file("ascii.stl"));
  test::write_stl_binary(s.mesh, s.file("binary.stl"));
  fuzz("stl ascii", s.file("ascii.stl"), "stl", try_mesh);
  fuzz("stl binary", s.file("binary.stl"), "stl", try_mesh);
}
TEST_CASE("fuzz: PLY mesh loader, ascii and binary") {
  Seeds s;
  test::write_ply_ascii(s.mesh, s.file("ascii.ply"));
  test::write_ply_binary(s.mesh, s.file("binary.ply"));
  fuzz("ply ascii", s.file("ascii.ply"), "ply", try_mesh);
  fuzz("ply binary", s.file("binary.ply"), "ply", try_mesh);
}
TEST_CASE("fuzz: OFF and SMF loaders") {
  Seeds s;
  test::write_off(s.mesh, s.file("seed.off"));
  test::write_smf(s.mesh, s.file("seed.smf"));
  fuzz("off", s.file("seed.off"), "off", try_mesh);
  fuzz("smf", s.file("seed.smf"), "smf", try_mesh);
}
TEST_CASE("fuzz: glTF loader, JSON and binary") {
  Seeds s;
  REQUIRE(test::write_gltf(s.mesh, s.file("seed.gltf"), false));
  REQUIRE(test::write_gltf(s.mesh, s.file("seed.glb"), true));
  fuzz("gltf", s.file("seed.gltf"), "gltf", try_mesh);
  fuzz("glb", s.file("seed.glb"), "glb", try_mesh);
}
TEST_CASE("fuzz: particle readers, PLY (binary and ascii) and CSV") {
  Seeds s;
  const ParticleSet set = test::random_particles(48, 5, true, true);
  write_particles(set, s.file("seed.ply"));
  write_particles(set, s.file("seed.csv"));
  std::string ascii = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                      "property float z\nproperty float radius\nend_header\n0 0 0 0.1\n1 0 0 0.1\n0 1 0 0.2\n";
  test::write_text(s.file("ascii.ply"), ascii);
  fuzz("particles ply", s.file("seed.ply"), "ply", try_particles);
  fuzz("particles ply ascii", s.file("ascii.ply"), "ply", try_particles);
  fuzz("particles csv", s.file("seed.csv"), "csv", try_particles);
}

// tests/fuzz_regressions/EXPECTED: what each kept input must give.
struct Expectation {
  bool valid = true;
  std::string text;                 // reject: the message contains it
  double volume = -1;               // valid: the volume (when >= 0)
  long parts = -1;                  // valid: the number of parts (when >= 0)
};

std::map<std::string, Expectation> read_expectations(const fs::path& file) {
  std::map<std::string, Expectation> out;
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream words(line);
    std::string name, kind;
    words >> name >> kind;
    Expectation e;
    e.valid = kind == "valid";
    if (!e.valid) {
      std::getline(words >> std::ws, e.text);
    } else {
      std::string key;
      while (words >> key) {
        if (key == "volume") words >> e.volume;
        if (key == "parts") words >> e.parts;
      }
    }
    out[name] = e;
  }
  return out;
}

TEST_CASE("fuzz regressions: every kept input gives what EXPECTED says, or a valid result or one pfill::Error") {
  const fs::path folder = fs::path(PFILL_SOURCE_TESTS) / "fuzz_regressions";
  const auto expected = read_expectations(folder / "EXPECTED");
  REQUIRE(expected.size() >= 4);
  size_t replayed = 0, asserted = 0;
  for (const auto& entry : fs::directory_iterator(folder)) {
    const std::string path = entry.path().string();
    const std::string name = entry.path().filename().string();
    if (name == "README.md" || name == "EXPECTED") continue;
    CAPTURE(path);
    const bool particles = name.find("particles") != std::string::npos || entry.path().extension() == ".csv";
    const Outcome outcome = (particles ? try_particles : try_mesh)(path);
    ++replayed;
    const auto it = expected.find(name);
    if (it == expected.end()) continue;
    ++asserted;
    const Expectation& e = it->second;
    if (!e.valid) {
      CHECK(outcome == Outcome::Rejected);
      CHECK_THROWS_WITH_AS(load_mesh(path), doctest::Contains(e.text.c_str()), Error);
      continue;
    }
    REQUIRE(outcome == Outcome::Valid);
    const Mesh m = load_mesh(path);
    const MeshDiagnostics d = diagnose(m);
    CHECK(d.misoriented_edges == 0);
    CHECK(!d.inside_out());
    if (e.volume >= 0) CHECK(d.volume() == doctest::Approx(e.volume).epsilon(1e-9));
    if (e.parts >= 0) CHECK(static_cast<long>(d.components) == e.parts);
  }
  MESSAGE(replayed << " regression inputs replayed, " << asserted << " against EXPECTED");
  CHECK(asserted == expected.size());  // every listed file is there
}

TEST_CASE("a FIFO as the mesh is refused at once, not opened or waited on") {
  test::TempDir dir("fifo");
  const std::string path = dir.file("mesh.obj");
  REQUIRE(::mkfifo(path.c_str(), 0600) == 0);
  CHECK_THROWS_WITH_AS(load_mesh(path), doctest::Contains("not a regular file"), Error);
}
