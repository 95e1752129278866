// Times the preview renderer on a large packing (default: 1e6 spheres in a
// ball at 1024x768) and, with --docs DIR, writes the README's example
// pictures. Usage:
//   bench_render [--count N] [--size WxH] [--trials K] [--aa N] [--ao N] [--docs DIR]
#include <tbb/info.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "pfill/error.hpp"
#include "pfill/render.hpp"
#include "pfill/shapes.hpp"

using namespace pfill;

namespace {

// A perceptual-ish ramp (dark blue -> teal -> yellow) for depth colouring.
Rgb8 ramp(double t) {
  static const double stops[4][3] = {{40, 30, 110}, {30, 130, 150}, {120, 200, 90}, {250, 225, 60}};
  t = std::clamp(t, 0.0, 1.0) * 3;
  const int i = std::min(2, static_cast<int>(t));
  const double f = t - i;
  Rgb8 c;
  for (int k = 0; k < 3; ++k) c[k] = static_cast<uint8_t>(std::lround(stops[i][k] * (1 - f) + stops[i + 1][k] * f));
  return c;
}

// Non-overlapping spheres of radius r on a jittered cubic lattice, kept where
// `depth` (distance inside the shape, negative outside) is at least r;
// coloured by depth.
template <typename Depth>
ParticleSet lattice_packing(const Box3& box, double r, Depth depth, double max_depth, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.09 * r, 0.09 * r);
  const double spacing = 2.2 * r;
  ParticleSet set;
  for (double z = box.lo.z; z <= box.hi.z; z += spacing)
    for (double y = box.lo.y; y <= box.hi.y; y += spacing)
      for (double x = box.lo.x; x <= box.hi.x; x += spacing) {
        const Vec3 p = Vec3(x, y, z) + Vec3(jitter(rng), jitter(rng), jitter(rng));
        const double d = depth(p);
        if (d < r) continue;
        set.positions.push_back(p);
        set.radii.push_back(r);
        set.colours.push_back(ramp(d / max_depth));
      }
  return set;
}

ParticleSet ball_packing(size_t count, uint32_t seed) {
  // Lattice density 1/(2.2 r)^3 in the unit ball gives about `count` spheres.
  const double r = std::cbrt(4.0 / 3.0 * M_PI / count) / 2.2;
  Box3 box;
  box.add(Vec3(-1, -1, -1));
  box.add(Vec3(1, 1, 1));
  return lattice_packing(box, r, [](const Vec3& p) { return 1.0 - length(p); }, 1.0, seed);
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void write_docs(const std::string& dir) {
  // The built-in torus (ring 1, tube 0.45 about z) filled with a lattice
  // packing, cut open at z = 0 (through the ring), with its shell.
  const Mesh torus = make_builtin("torus");
  const double ring = 1.0, tube = 0.45;
  Box3 box = torus.bounds();
  const ParticleSet in_torus = lattice_packing(
      box, 0.035,
      [&](const Vec3& p) { return tube - std::hypot(std::hypot(p.x, p.y) - ring, p.z); }, tube, 7);
  RenderOptions options;
  options.width = 640;
  options.height = 420;
  options.samples_per_axis = 2;
  options.cut = parse_cut("z=0");
  write_png(render(in_torus, &torus, options), dir + "/torus_cut.png");
  std::printf("docs: %s/torus_cut.png (%zu particles)\n", dir.c_str(), in_torus.size());

  // The built-in sphere, cut open at its centre.
  const Mesh sphere = make_builtin("sphere");
  const ParticleSet in_sphere = lattice_packing(
      sphere.bounds(), 0.05, [](const Vec3& p) { return 0.995 - length(p); }, 1.0, 3);
  options.width = 420;
  options.height = 420;
  options.cut = parse_cut("z");
  write_png(render(in_sphere, &sphere, options), dir + "/sphere_cut.png");
  std::printf("docs: %s/sphere_cut.png (%zu particles)\n", dir.c_str(), in_sphere.size());
}

}  // namespace

int main(int argc, char** argv) try {
  size_t count = 1000000;
  int width = 1024, height = 768, trials = 3, aa = 1, ao = 6;
  std::string docs;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i], value = argv[i + 1];
    if (flag == "--count") count = std::stoul(value);
    else if (flag == "--size") std::sscanf(value.c_str(), "%dx%d", &width, &height);
    else if (flag == "--trials") trials = std::stoi(value);
    else if (flag == "--aa") aa = std::stoi(value);
    else if (flag == "--ao") ao = std::stoi(value);
    else if (flag == "--docs") docs = value;
    else throw Error("unknown option " + flag);
  }
  if (!docs.empty()) write_docs(docs);

  auto start = std::chrono::steady_clock::now();
  const ParticleSet particles = ball_packing(count, 1);
  std::printf("packing: %zu spheres of radius %.5f in the unit ball (%.2f s to make)\n", particles.size(),
              particles.radii[0], seconds_since(start));
  RenderOptions options;
  options.width = width;
  options.height = height;
  options.samples_per_axis = aa;
  options.ambient_occlusion_rays = ao;

  RenderOptions warm = options;
  warm.width = 64;
  warm.height = 48;
  render(particles, nullptr, warm);  // warm-up: threads, allocations

  std::vector<double> times, cut_times;
  for (int t = 0; t < trials; ++t) {
    start = std::chrono::steady_clock::now();
    const Image image = render(particles, nullptr, options);
    times.push_back(seconds_since(start));
    if (image.at(width / 2, height / 2) == background_at(options, height / 2, height))
      throw Error("verification failed: the centre pixel shows no sphere");
  }
  options.cut = parse_cut("z");
  for (int t = 0; t < trials; ++t) {
    start = std::chrono::steady_clock::now();
    render(particles, nullptr, options);
    cut_times.push_back(seconds_since(start));
  }
  std::sort(times.begin(), times.end());
  std::sort(cut_times.begin(), cut_times.end());
  std::printf("render %zu spheres at %dx%d, %dx%d samples, %d AO rays, %d threads: median %.3f s "
              "(min %.3f), cut z: median %.3f s (%d trials)\n",
              particles.size(), width, height, aa, aa, ao, tbb::info::default_concurrency(),
              times[times.size() / 2], times.front(), cut_times[cut_times.size() / 2], trials);
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "bench_render: %s\n", e.what());
  return 1;
}
