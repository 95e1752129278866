// The fill's exact check (fill_verify.hpp).
#include "fill/fill_verify.hpp"

#include <random>

#include "fill/size_deficit.hpp"
#include "pfill/colour.hpp"
#include "pfill/packing_metrics.hpp"

namespace pfill {
namespace {

// Most holes the exact check fills (a search for each equal sphere); the finish fills the
// many its field shows, so only a few near the wall are left here.
constexpr int kMostExactHoles = 32;

/// Holes the field hid (near the wall) or the repair opened take a sphere
/// where, by exact distances, one fits inside without overlap (a hole fits
/// a sphere at the rest distance: 2r, or more for sparse fills). Each
/// search's distinct holes that still fit, then a new search (a search
/// reads every sphere: at 1e6, whose coarse field left 4 such holes, one
/// at a time took five in a verify of 34-44 s). Equal spheres: only holes
/// no sphere of this round came near (the next search may find such a one
/// wider elsewhere), so they fill as one hole a search did. Unequal ones
/// (of a class short of its share that fits; none: the distribution comes
/// first): every hole that still fits, as a search at the smallest radius
/// costs many times an equal fill's. Returns
/// the widest hole left. Held in parts: every process walks the same holes
/// (of all processes) alike, on the size classes' counts summed over the
/// processes and the spheres this round placed on any, and the one whose
/// region holds a hole takes its sphere.
Hole fill_exact_holes(const Boundary& boundary, double radius, std::optional<SizeDeficit>& deficit,
                      const FillOptions& o, const ParticleShare& share, ParticleSet& particles, uint64_t& next_id,
                      FillResult& result) {
  std::mt19937_64 rng(o.seed);
  const bool velocities = share.group->max(particles.has_velocities() ? 1.0 : 0.0) > 0;
  std::vector<Hole> holes = largest_holes(boundary, particles, radius, share);
  int filled = 0;
  while (o.hole_rounds > 0 && filled < kMostExactHoles) {
    ParticleSet placed;  // this round's spheres, on every process
    if (deficit) deficit->recount(particles.radii, particles.size(), *share.group);
    for (size_t k = 0; k < holes.size() && filled < kMostExactHoles; ++k) {
      const double found = holes[k].gap_over_r * radius;
      double gap = found;  // (less any sphere this round put near it)
      for (size_t m = 0; m < placed.size(); ++m)
        gap = std::min(gap, length(placed.positions[m] - holes[k].centre) - placed.radii[m]);
      if (!deficit && gap < found) continue;
      const double depth = -boundary.signed_distance(holes[k].centre);
      if (gap < (2 * o.rest_distance - 1) * radius || depth < radius) continue;
      double r = radius;
      if (deficit) {
        r = deficit->take_within(std::min(gap, depth), rng);  // (counted in)
        if (r == 0) continue;
      }
      placed.positions.push_back(holes[k].centre);
      placed.radii.push_back(r);
      const uint64_t id = next_id++;
      ++result.holes_filled;
      ++filled;
      if (!share.owns(holes[k].centre)) continue;
      particles.positions.push_back(holes[k].centre);
      particles.radii.push_back(r);
      particles.ids.push_back(id);
      if (velocities) particles.velocities.push_back({});
    }
    if (placed.size() == 0) break;
    holes = largest_holes(boundary, particles, radius, share);
  }
  return holes.front();
}

}  // namespace

void verify_fill(const Boundary& boundary, const Mesh& mesh, double volume, double radius,
                 const std::optional<RadiusDistribution>& sizes, const std::vector<size_t>& size_caps,
                 const FillOptions& o, ParticleSet particles, const ParticleShare& share, uint64_t& next_id,
                 FillResult& result) {
  result.containment = repair_containment(boundary, particles, o.containment_tolerance, o.max_overlap, share);
  std::optional<SizeDeficit> deficit;
  if (sizes) {
    deficit.emplace(*sizes);
    deficit->set_caps(size_caps);
  }
  const Hole h = fill_exact_holes(boundary, radius, deficit, o, share, particles, next_id, result);
  MetricsOptions mo;
  mo.containment_tolerance = o.containment_tolerance;
  mo.holes = false;  // measured just now
  result.metrics = measure_packing(boundary, volume, particles, mo, share);
  result.metrics.largest_hole = h.gap_over_r;
  if (sizes) {
    result.radii = sizes;
    result.radii_fit = compare_distribution(*sizes, particles.radii, share);
  }
  const ColourOptions colour = o.colour ? *o.colour : ColourOptions{default_colour_mode(mesh), {}};
  // (the depth colours' scale: the deepest sphere of all, where each process holds its own)
  std::function<double(double)> deepest_of_all;
  if (!share.complete()) deepest_of_all = [&share](double d) { return share.group->max(d); };
  const std::string note = colour_particles(boundary, particles, colour, deepest_of_all);
  if (!note.empty()) result.warnings.push_back(note);
  result.particles = std::move(particles);
}

}  // namespace pfill
