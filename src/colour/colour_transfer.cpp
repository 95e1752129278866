// Colour transfer from the surface to the particles: closest points in
// batches (Boundary::closest, parallel), then the colour of each point in
// parallel.
#include <functional>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

#include "pfill/colour.hpp"
#include "pfill/error.hpp"

namespace pfill {
namespace {

// Points per batch of closest-point queries: bounds the memory of the
// ClosestPoint records on large fills.
constexpr size_t kBatch = size_t(1) << 16;

template <typename PerBatch>
void for_each_batch(const std::vector<Vec3>& points, const Boundary& boundary, PerBatch per_batch) {
  std::vector<Vec3> batch;
  for (size_t begin = 0; begin < points.size(); begin += kBatch) {
    const size_t end = std::min(points.size(), begin + kBatch);
    batch.assign(points.begin() + static_cast<std::ptrdiff_t>(begin), points.begin() + static_cast<std::ptrdiff_t>(end));
    per_batch(begin, boundary.closest(batch));
  }
}

void colour_by_surface(const Boundary& boundary, const std::vector<Vec3>& points, std::vector<Rgb8>& colours) {
  const Mesh& mesh = boundary.mesh();
  check_surface_colour_inputs(mesh);
  for_each_batch(points, boundary, [&](size_t offset, const std::vector<ClosestPoint>& closest) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, closest.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i)
        colours[offset + i] = encode_srgb8(surface_colour(mesh, closest[i].triangle, closest[i].u, closest[i].v));
    });
  });
}

void colour_by_depth(const Boundary& boundary, const std::vector<Vec3>& points, std::vector<Rgb8>& colours,
                     const std::function<double(double)>& deepest_of_all) {
  std::vector<double> depth(points.size());
  for_each_batch(points, boundary, [&](size_t offset, const std::vector<ClosestPoint>& closest) {
    for (size_t i = 0; i < closest.size(); ++i) depth[offset + i] = closest[i].distance;
  });
  double deepest = depth.empty() ? 0.0 : *std::max_element(depth.begin(), depth.end());
  if (deepest_of_all) deepest = deepest_of_all(deepest);
  for (size_t i = 0; i < points.size(); ++i) colours[i] = depth_colour(deepest > 0 ? depth[i] / deepest : 0.0);
}

}  // namespace

ColourTransfer transfer_colours(const Boundary& boundary, const std::vector<Vec3>& points,
                                const ColourOptions& options, const std::function<double(double)>& deepest_of_all) {
  ColourTransfer out;
  out.applied = options.mode;
  if (options.mode == ColourMode::Surface && !has_surface_colour(boundary.mesh())) {
    out.applied = ColourMode::Depth;
    out.note = "'" + boundary.mesh().source +
               "' has no vertex colours, texture or material colour: particles are coloured by depth instead";
  }
  for (const Vec3& p : points)
    if (!is_finite(p)) throw Error("colour transfer: a particle position is not finite");
  switch (out.applied) {
    case ColourMode::None: break;
    case ColourMode::Constant: out.colours.assign(points.size(), options.constant); break;
    case ColourMode::Surface:
      out.colours.resize(points.size());
      colour_by_surface(boundary, points, out.colours);
      break;
    case ColourMode::Depth:
      out.colours.resize(points.size());
      colour_by_depth(boundary, points, out.colours, deepest_of_all);
      break;
  }
  return out;
}

std::string colour_particles(const Boundary& boundary, ParticleSet& particles, const ColourOptions& options,
                             const std::function<double(double)>& deepest_of_all) {
  ColourTransfer result = transfer_colours(boundary, particles.positions, options, deepest_of_all);
  particles.colours = std::move(result.colours);
  return result.note;
}

}  // namespace pfill
