// The fill's exact check (fill_verify.hpp).
#include "fill/fill_verify.hpp"

#include <random>

#include "fill/size_deficit.hpp"
#include "pfill/colour.hpp"
#include "pfill/packing_metrics.hpp"

namespace pfill {
namespace {

// Most holes the exact check fills, one search each; the finish fills the
// many its field shows, so only a few near the wall are left here.
constexpr int kMostExactHoles = 32;

}  // namespace

void verify_fill(const Boundary& boundary, const Mesh& mesh, double volume, double radius,
                 const std::optional<RadiusDistribution>& sizes, const FillOptions& o, ParticleSet particles,
                 uint64_t& next_id, FillResult& result) {
  result.containment = repair_containment(boundary, particles, o.containment_tolerance, o.max_overlap);
  // Holes the field hid (near the wall) or the repair opened take a sphere
  // where, by exact distances, one fits inside without overlap (a hole fits
  // a sphere at the rest distance: 2r, or more for sparse fills). The exact
  // inside test (a majority of rays on open meshes) has the last word.
  std::optional<SizeDeficit> deficit;
  if (sizes) deficit.emplace(*sizes);
  std::mt19937_64 rng(o.seed);
  Hole h = largest_hole(boundary, particles, radius);
  for (int k = 0; k < kMostExactHoles && o.hole_rounds > 0 && h.gap_over_r >= 2 * o.rest_distance - 1 &&
                  boundary.signed_distance(h.centre) <= -radius;
       ++k) {
    double r = radius;
    if (deficit) {  // of a class short of its share that fits; none: the distribution comes first
      deficit->recount(particles.radii);
      r = deficit->take_within(std::min(h.gap_over_r * radius, -boundary.signed_distance(h.centre)), rng);
      if (r == 0) break;
    }
    particles.positions.push_back(h.centre);
    particles.radii.push_back(r);
    particles.ids.push_back(next_id++);
    if (particles.has_velocities()) particles.velocities.push_back({});
    ++result.holes_filled;
    h = largest_hole(boundary, particles, radius);
  }
  MetricsOptions mo;
  mo.containment_tolerance = o.containment_tolerance;
  mo.holes = false;  // measured just now
  result.metrics = measure_packing(boundary, volume, particles, mo);
  result.metrics.largest_hole = h.gap_over_r;
  if (sizes) {
    result.radii = sizes;
    result.radii_fit = compare_distribution(*sizes, particles.radii);
  }
  const ColourOptions colour = o.colour ? *o.colour : ColourOptions{default_colour_mode(mesh), {}};
  const std::string note = colour_particles(boundary, particles, colour);
  if (!note.empty()) result.warnings.push_back(note);
  result.particles = std::move(particles);
}

}  // namespace pfill
