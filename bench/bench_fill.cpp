// bench_fill: whole fills of the reference meshes at the radii where the
// clipped hexagonal lattice packs 3,626 (spot) and 3,643 (bunny) spheres,
// plus the built-in torus; prints count, packing fraction, containment,
// overlaps and wall time against the lattice anchors, as text and JSON.
//
//   bench_fill [--mesh spot|bunny|torus|all] [--seeds N] [--stop-compare]
//              [--device SPEC] [--json FILE]
//
// --stop-compare fills spot once per stopping signal (blocked, ke,
// collisions) and reports what each gives.
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pfill/error.hpp"
#include "pfill/fill.hpp"
#include "pfill/mesh_io.hpp"
#include "pfill/shapes.hpp"

using namespace pfill;

namespace {

struct Case {
  std::string name;
  std::string file;        // under the shared meshes, or "" for built-in
  double radius;           // in the file's units
  size_t lattice_count;    // the clipped lattice's count (0: none known)
  double lattice_packing;
};

const Case kCases[] = {
    {"spot", "spot.obj", 0.030160, 3626, 0.580},
    {"bunny", "stanford-bunny-closed.obj", 0.012253, 3643, 0.583},
    {"torus", "", 0.0, 0, 0},
};

nlohmann::ordered_json run_case(const Case& c, const Mesh& mesh, uint64_t seed, StopCriterion stop,
                                const std::string& device) {
  FillOptions o;
  if (c.radius > 0) o.radius = c.radius;
  else o.count = 4000;
  o.seed = seed;
  o.stop = stop;
  o.device = device;
  o.colour = ColourOptions{ColourMode::None, {}};
  const auto t0 = std::chrono::steady_clock::now();
  const FillResult r = fill(mesh, o);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const PackingMetrics& m = r.metrics;
  std::printf("%-6s seed %-3llu stop %-10s | %5zu spheres  phi %.4f  inside %6.2f%%  pen %5.2f%%r  "
              "overlap max %5.2f%%r mean %5.2f%%r | %6.1fs (field %.1fs) %8llu steps %7.0f steps/s | %s",
              c.name.c_str(), static_cast<unsigned long long>(seed), to_string(stop), m.count, m.packing_fraction,
              100 * m.contained_share, 100 * m.max_penetration, 100 * m.max_overlap, 100 * m.mean_overlap, wall,
              r.field_seconds, static_cast<unsigned long long>(r.steps), r.steps / std::max(1e-9, wall - r.field_seconds),
              r.stop_signal.c_str());
  if (c.lattice_count)
    std::printf("  (lattice %zu / %.3f: %+.1f%%)", c.lattice_count, c.lattice_packing,
                100.0 * (static_cast<double>(m.count) / c.lattice_count - 1));
  std::printf("\n");
  std::fflush(stdout);
  nlohmann::ordered_json passes = nlohmann::ordered_json::array();
  for (const PassStats& p : r.passes) passes.push_back({{"pass", p.name}, {"steps", p.steps}, {"seconds", p.seconds}});
  return {{"mesh", c.name},
          {"radius", r.radius},
          {"seed", seed},
          {"stop", to_string(stop)},
          {"stop_signal", r.stop_signal},
          {"count", m.count},
          {"packing_fraction", m.packing_fraction},
          {"contained_share", m.contained_share},
          {"max_penetration", m.max_penetration},
          {"max_overlap", m.max_overlap},
          {"mean_overlap", m.mean_overlap},
          {"coordination", m.mean_coordination},
          {"max_parts", r.max_parts},
          {"relief_removed", r.relief_removed},
          {"voids_filled", r.voids_filled},
          {"containment_removed", r.containment.removed},
          {"lattice_count", c.lattice_count},
          {"lattice_packing", c.lattice_packing},
          {"seconds", wall},
          {"field_seconds", r.field_seconds},
          {"steps", r.steps},
          {"passes", passes},
          {"device", r.device}};
}

}  // namespace

int main(int argc, char** argv) {
  std::string which = "all", json_path, device;
  int seeds = 1;
  bool stop_compare = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw Error(a + " needs a value");
      return argv[++i];
    };
    if (a == "--mesh") which = value();
    else if (a == "--seeds") seeds = std::stoi(value());
    else if (a == "--json") json_path = value();
    else if (a == "--device") device = value();
    else if (a == "--stop-compare") stop_compare = true;
    else {
      std::fprintf(stderr, "usage: bench_fill [--mesh spot|bunny|torus|all] [--seeds N] [--stop-compare] "
                           "[--device SPEC] [--json FILE]\n");
      return 2;
    }
  }
  const std::filesystem::path shared = PFILL_SHARED_MESHES;
  nlohmann::ordered_json runs = nlohmann::ordered_json::array();
  try {
    for (const Case& c : kCases) {
      if (which != "all" && which != c.name) continue;
      Mesh mesh;
      if (c.file.empty()) {
        mesh = make_builtin(c.name);
      } else if (std::filesystem::exists(shared / c.file)) {
        mesh = load_mesh((shared / c.file).string());
      } else {
        std::printf("%-6s skipped: %s not found\n", c.name.c_str(), (shared / c.file).c_str());
        continue;
      }
      for (int s = 1; s <= seeds; ++s) runs.push_back(run_case(c, mesh, s, StopCriterion::Blocked, device));
      if (stop_compare && c.name == "spot")
        for (StopCriterion stop : {StopCriterion::KineticEnergy, StopCriterion::Collisions})
          runs.push_back(run_case(c, mesh, 1, stop, device));
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_fill: %s\n", e.what());
    return 1;
  }
  if (!json_path.empty()) {
    std::ofstream(json_path) << nlohmann::ordered_json{{"bench", "fill"}, {"runs", runs}}.dump(2) << "\n";
    std::printf("wrote %s\n", json_path.c_str());
  }
  return 0;
}
