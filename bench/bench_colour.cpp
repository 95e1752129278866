// Times colour transfer (closest point + texture sample) on many points
// inside Spot (default 1e6) and, with --docs DIR, writes the README's picture
// of a lattice packing inside spot_textured.glb coloured from her texture.
// Usage:
//   bench_colour [--mesh FILE] [--count N] [--trials K] [--spheres N] [--view V] [--cut C] [--docs DIR]
#include <tbb/info.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "pfill/boundary.hpp"
#include "pfill/colour.hpp"
#include "pfill/error.hpp"
#include "pfill/mesh_io.hpp"
#include "pfill/render.hpp"

using namespace pfill;

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Face-centred cubic lattice of touching spheres of radius r over `box`,
// kept where the whole sphere is inside (signed distance < -r).
ParticleSet lattice_packing(const Boundary& boundary, double r) {
  const Box3 box = boundary.mesh().bounds();
  const double a = 2 * std::sqrt(2.0) * r;  // cube edge: neighbours at distance 2r
  const Vec3 basis[4] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  std::vector<Vec3> candidates;
  for (double z = box.lo.z; z <= box.hi.z; z += a)
    for (double y = box.lo.y; y <= box.hi.y; y += a)
      for (double x = box.lo.x; x <= box.hi.x; x += a)
        for (const Vec3& b : basis) candidates.push_back(Vec3(x, y, z) + b * a);
  const std::vector<double> sd = boundary.signed_distance(candidates);
  ParticleSet set;
  for (size_t i = 0; i < candidates.size(); ++i)
    if (sd[i] < -r) {
      set.positions.push_back(candidates[i]);
      set.radii.push_back(r);
    }
  return set;
}

void write_docs(const Boundary& boundary, size_t spheres, const std::string& view, const std::string& cut,
                const std::string& dir) {
  // Radius for about `spheres` spheres: a clipped lattice fills ~58% of the
  // volume (shared/meshes/MANIFEST.md).
  const double volume = std::fabs(boundary.signed_volume());
  const double r = std::cbrt(0.58 * volume / (spheres * 4.0 / 3.0 * M_PI));
  ParticleSet packing = lattice_packing(boundary, r);
  const std::string note = colour_particles(boundary, packing, {});
  if (!note.empty()) std::printf("note: %s\n", note.c_str());
  RenderOptions options;
  options.width = 640;
  options.height = 480;
  options.samples_per_axis = 2;
  options.view = parse_view(view);
  if (!cut.empty()) options.cut = parse_cut(cut);
  const std::string path = dir + "/spot_colours.png";
  write_png(render(packing, &boundary.mesh(), options), path);
  std::printf("docs: %s (%zu spheres of radius %.5f, view %s, cut %s)\n", path.c_str(), packing.size(), r,
              view.c_str(), cut.c_str());
}

}  // namespace

int main(int argc, char** argv) try {
  std::string mesh_path = std::string(PFILL_SHARED_MESHES) + "/spot_textured.glb";
  size_t count = 1000000, spheres = 20000;
  int trials = 3;
  std::string docs, view = "three-quarter", cut = "x";
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i], value = argv[i + 1];
    if (flag == "--mesh") mesh_path = value;
    else if (flag == "--count") count = std::stoul(value);
    else if (flag == "--trials") trials = std::stoi(value);
    else if (flag == "--spheres") spheres = std::stoul(value);
    else if (flag == "--view") view = value;
    else if (flag == "--cut") cut = value;
    else if (flag == "--docs") docs = value;
    else throw Error("unknown option " + flag);
  }
  const Mesh mesh = load_mesh(mesh_path);
  const Boundary boundary(mesh);
  if (!docs.empty()) write_docs(boundary, spheres, view, cut, docs);

  // Points uniform in the bounding box: inside and outside, like a fill's
  // particles plus strays; every one needs a closest point and a colour.
  const Box3 box = mesh.bounds();
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u01(0, 1);
  std::vector<Vec3> points(count);
  for (Vec3& p : points) p = box.lo + Vec3(u01(rng) * box.size().x, u01(rng) * box.size().y, u01(rng) * box.size().z);

  transfer_colours(boundary, std::vector<Vec3>(points.begin(), points.begin() + std::min<size_t>(count, 10000)), {});
  std::vector<double> times;
  ColourTransfer result;
  for (int t = 0; t < trials; ++t) {
    const auto start = std::chrono::steady_clock::now();
    result = transfer_colours(boundary, points, {});
    times.push_back(seconds_since(start));
  }
  const std::set<Rgb8> distinct(result.colours.begin(), result.colours.end());
  if (result.colours.size() != count || (count > 1000 && distinct.size() < 10))
    throw Error("verification failed: missing colours or all alike");
  // Depth needs the closest points only: the difference is the cost of the
  // surface colour (interpolation and texture sampling).
  std::vector<double> depth_times;
  for (int t = 0; t < trials; ++t) {
    const auto start = std::chrono::steady_clock::now();
    transfer_colours(boundary, points, {ColourMode::Depth, {}});
    depth_times.push_back(seconds_since(start));
  }
  std::sort(times.begin(), times.end());
  std::sort(depth_times.begin(), depth_times.end());
  std::printf("transfer_colours (%s) on %zu points, %s (%zu triangles, %zu textures), %d threads: median %.3f s "
              "(min %.3f, %.2f us/point, %zu distinct colours, %d trials)\n",
              colour_mode_name(result.applied).c_str(), count, mesh_path.c_str(), mesh.triangle_count(),
              mesh.textures.size(), tbb::info::default_concurrency(), times[times.size() / 2], times.front(),
              1e6 * times[times.size() / 2] / std::max<size_t>(count, 1), distinct.size(), trials);
  std::printf("transfer_colours (depth, closest points only) on the same points: median %.3f s\n",
              depth_times[depth_times.size() / 2]);
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "bench_colour: %s\n", e.what());
  return 1;
}
