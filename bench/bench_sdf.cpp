// bench_sdf: build time and memory of the signed distance field, 64^3 to
// 512^3 (samples on the longest axis), on the shared meshes (or a generated
// torus when ../shared/meshes is absent). Warms up, verifies each field
// against exact queries, reports the median of several builds.
//
//   bench_sdf [--sizes 64,128,256,512] [--trials N] [--band-spacings B]
//             [--outer-band-spacings B (outside the solid; default the same)]
//   bench_sdf --fill-radius R [--trials N] MESH.obj
//
// --fill-radius R: the field a fill at particle radius R builds (spacing
// 0.33 R, coarsened as the fill does past 2^26 samples; margin 2 R + 3
// spacings), with the fill's bands before issue 32
// (max(3 R, 4 spacings) on both sides) and now (the fill's plan:
// fill_plan.cpp), built in turn N times each; prints wall and CPU
// seconds, exact queries and the deepest value of each build.
//             [--threads T] [--json FILE] [MESH.obj ...]
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "fill/fill_plan.hpp"
#include "pfill/boundary.hpp"
#include "pfill/error.hpp"
#include "pfill/mesh_diagnostics.hpp"
#include "pfill/mesh_io.hpp"
#include "pfill/sdf.hpp"
#include "pfill/shapes.hpp"

using namespace pfill;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Largest |sample - exact| at random points whose cell lies in the band, and
// the number of sign disagreements with inside() at random points deeper
// than one cell.
struct Verification {
  double max_band_error = 0;
  int band_points = 0;
  int sign_errors = 0;
  int sign_points = 0;
};

Verification verify(const Boundary& boundary, const ScalarGrid& grid, double inner_band, double outer_band) {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Vec3 size = grid.upper() - grid.origin;
  const double diagonal = grid.spacing * std::sqrt(3.0);
  Verification v;
  for (int n = 0; n < 4000; ++n) {
    const Vec3 p = grid.origin + Vec3(u(rng) * size.x, u(rng) * size.y, u(rng) * size.z);
    const double exact = boundary.signed_distance(p);
    const double value = sample(grid, p);
    if (std::fabs(exact) < (exact > 0 ? outer_band : inner_band) - diagonal) {
      v.max_band_error = std::max(v.max_band_error, std::fabs(value - exact));
      ++v.band_points;
    }
    if (std::fabs(exact) > diagonal) {
      v.sign_errors += (value < 0) != (exact < 0);
      ++v.sign_points;
    }
  }
  return v;
}

std::vector<int> parse_sizes(const std::string& text) {
  std::vector<int> sizes;
  std::stringstream s(text);
  std::string item;
  while (std::getline(s, item, ',')) sizes.push_back(std::stoi(item));
  return sizes;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    std::vector<int> sizes = {64, 128, 256, 512};
    int trials = 3;
    double band_spacings = 4;
    double outer_band_spacings = -1;
    int threads = 0;
    std::string json_path;
    std::vector<std::string> mesh_paths;
    double fill_radius = 0;
    for (int i = 1; i < argc; ++i) {
      const std::string arg = argv[i];
      auto next = [&]() -> std::string {
        if (i + 1 >= argc) throw Error(arg + " needs a value");
        return argv[++i];
      };
      if (arg == "--sizes") sizes = parse_sizes(next());
      else if (arg == "--trials") trials = std::max(1, std::stoi(next()));
      else if (arg == "--band-spacings") band_spacings = std::stod(next());
      else if (arg == "--outer-band-spacings") outer_band_spacings = std::stod(next());
      else if (arg == "--threads") threads = std::stoi(next());
      else if (arg == "--fill-radius") fill_radius = std::stod(next());
      else if (arg == "--json") json_path = next();
      else if (arg == "--help" || arg == "-h") {
        std::cout << "bench_sdf [--sizes 64,128,256,512] [--trials N] [--band-spacings B] "
                     "[--outer-band-spacings B] [--threads T] [--json FILE] [MESH.obj ...]\n";
        return 0;
      } else mesh_paths.push_back(arg);
    }
    std::unique_ptr<tbb::global_control> limit;
    if (threads > 0)
      limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads);

    std::vector<Mesh> meshes;
    if (mesh_paths.empty()) {
      const std::filesystem::path shared(PFILL_SHARED_MESHES);
      for (const char* name : {"stanford-bunny-closed.obj", "spot.obj"})
        if (std::filesystem::exists(shared / name)) mesh_paths.push_back((shared / name).string());
    }
    for (const std::string& path : mesh_paths) meshes.push_back(load_mesh(path));
    if (meshes.empty()) {
      meshes.push_back(make_torus(1.0, 0.4, 256, 128));
      meshes.back().source = "generated torus (R 1, r 0.4, 65,536 triangles)";
    }

    if (fill_radius > 0) {  // the fill's field, its bands before and after issue 32, in turn
      for (const Mesh& mesh : meshes) {
        const Boundary boundary(mesh);
        FillOptions o;
        o.radius = fill_radius;
        const SdfOptions now = plan_fill(mesh.bounds(), diagnose(mesh), o).field;
        SdfOptions before(now.spacing);  // the same lattice, both bands max(3 R, 4 spacings)
        before.margin = now.margin;
        before.band = std::max(3 * fill_radius, 4 * now.spacing);
        for (int t = 0; t < trials; ++t)
          for (int v = 0; v < 2; ++v) {
            SdfStats st;
            const std::clock_t cpu0 = std::clock();
            const ScalarGrid grid = build_signed_distance_field(boundary, v ? now : before, &st);
            const double cpu = double(std::clock() - cpu0) / CLOCKS_PER_SEC;
            const float deepest = *std::min_element(grid.values.begin(), grid.values.end());
            std::printf("%s %s: %zu samples, wall %.3f s, CPU %.3f s, %zu exact, deepest %.6f\n",
                        std::filesystem::path(mesh.source).filename().string().c_str(), v ? "now   " : "before",
                        st.samples, st.seconds, cpu, st.exact_queries, -static_cast<double>(deepest));
            std::fflush(stdout);
          }
      }
      return 0;
    }

    nlohmann::json rows = nlohmann::json::array();
    std::printf("%-28s %9s %5s %15s %12s %9s %8s %9s %11s %8s %10s %7s\n", "mesh", "triangles", "n", "dims",
                "cells", "seconds", "cpu_s", "MB", "exact", "parity", "band_err", "signs");
    for (const Mesh& mesh : meshes) {
      const auto t0 = std::chrono::steady_clock::now();
      const Boundary boundary(mesh);
      const double boundary_seconds = seconds_since(t0);
      const std::string name = std::filesystem::path(mesh.source).filename().string();
      {  // warm-up: thread pool, caches
        SdfOptions warm(spacing_for_resolution(mesh.bounds(), 32));
        build_signed_distance_field(boundary, warm);
      }
      for (int n : sizes) {
        SdfOptions options(spacing_for_resolution(mesh.bounds(), n));
        options.band = band_spacings * options.spacing;
        if (outer_band_spacings >= 0) options.outer_band = outer_band_spacings * options.spacing;
        const int runs = n > 256 ? 1 : trials;
        std::vector<double> times, cpu_times;
        SdfStats stats;
        ScalarGrid grid;
        for (int t = 0; t < runs; ++t) {
          grid = ScalarGrid{};
          const std::clock_t cpu0 = std::clock();
          grid = build_signed_distance_field(boundary, options, &stats);
          cpu_times.push_back(double(std::clock() - cpu0) / CLOCKS_PER_SEC);
          times.push_back(stats.seconds);
        }
        std::sort(times.begin(), times.end());
        std::sort(cpu_times.begin(), cpu_times.end());
        const double median = times[times.size() / 2];
        const double cpu_median = cpu_times[cpu_times.size() / 2];
        const Verification check = verify(boundary, grid, stats.band, stats.outer_band);
        const std::string dims = std::to_string(stats.dims[0]) + "x" + std::to_string(stats.dims[1]) + "x" +
                                 std::to_string(stats.dims[2]);
        std::printf("%-28s %9zu %5d %15s %12zu %9.3f %8.2f %9.1f %11zu %8zu %10.2e %3d/%d\n", name.c_str(),
                    stats.triangles, n, dims.c_str(), stats.samples, median, cpu_median, stats.bytes / 1048576.0,
                    stats.exact_queries, stats.parity_queries, check.max_band_error, check.sign_errors,
                    check.sign_points);
        std::fflush(stdout);
        rows.push_back({{"mesh", name},
                        {"triangles", stats.triangles},
                        {"samples_longest_axis", n},
                        {"dims", stats.dims},
                        {"cells", stats.samples},
                        {"seconds_median", median},
                        {"seconds_all", times},
                        {"cpu_seconds_median", cpu_median},
                        {"bytes", stats.bytes},
                        {"megabytes", stats.bytes / 1048576.0},
                        {"scratch_bytes", stats.scratch_bytes},
                        {"exact_queries", stats.exact_queries},
                        {"parity_queries", stats.parity_queries},
                        {"spacing", options.spacing},
                        {"band", stats.band},
                        {"outer_band", stats.outer_band},
                        {"octree_levels", stats.levels},
                        {"boundary_build_seconds", boundary_seconds},
                        {"verify_max_band_error", check.max_band_error},
                        {"verify_band_points", check.band_points},
                        {"verify_sign_errors", check.sign_errors},
                        {"verify_sign_points", check.sign_points}});
      }
    }
    const nlohmann::json report = {{"benchmark", "bench_sdf"},
                                   {"threads", threads > 0 ? threads : static_cast<int>(
                                                                           tbb::global_control::active_value(
                                                                               tbb::global_control::max_allowed_parallelism))},
                                   {"rows", rows}};
    if (json_path.empty() || json_path == "-") {
      std::cout << report.dump(2) << "\n";
    } else {
      std::ofstream out(json_path);
      if (!out) throw Error(json_path + ": cannot write the JSON report");
      out << report.dump(2) << "\n";
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_sdf: %s\n", e.what());
    return 1;
  }
}
