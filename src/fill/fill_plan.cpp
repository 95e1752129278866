// The plan of a fill (fill_plan.hpp).
#include "fill/fill_plan.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "fill/fill_options_check.hpp"
#include "pfill/boundary.hpp"
#include "pfill/device/device.hpp"
#include "pfill/error.hpp"
#include "fill/short_number.hpp"

namespace pfill {
namespace {

// The top speed, in sigma per tau: a step's largest move is this times the
// step (0.1 sigma at the report's step).
constexpr double kTopSpeed = 10;
// Time between waves, in tau (24 steps of a wave's step): slower waves
// compress more gently and pack denser, while pass 1 stays at about the
// same number of steps at any count.
constexpr double kWaveEveryTau = 0.48;
// Patience, in tau: 1,500 steps at the report's step.
constexpr double kPatienceTau = 15;
// The automatic schedule's switch to waves (FillOptions::sites = -1): below
// this count the report's two sites pack denser and take no longer; from it
// on, waves are faster.
constexpr size_t kWavesFrom = 2000;
// Room test radii, in rest distances: 0.5 packs densest at the report's
// sites; over many sites it overfills, and the finish then deletes more.
constexpr double kSiteClearance = 0.5, kWaveClearance = 0.55;
// Device memory a particle slot needs, counted generously (the capacity
// may double), on top of the field.
constexpr double kDeviceBytesPerParticle = 2 * 96;
constexpr double kDeviceBytesFixed = 1024 * 96;

}  // namespace

std::optional<RadiusDistribution> fill_sizes(const FillOptions& o, double volume, double area) {
  if (!o.radii) return std::nullopt;
  RadiusDistribution d = *o.radii;
  // radii_by volume re-reads a SPEC parsed by number (the settings parse
  // `radii` before knowing it); a C++ caller's own basis otherwise stands.
  if (o.radii_by == FractionBasis::Volume && d.basis() != FractionBasis::Volume && !d.spec().empty())
    d = RadiusDistribution::parse(d.spec(), o.radii_by);
  if (o.count > 0) d = d.scaled(fill_scale_for_count(volume, area, o.count, d, o.max_overlap));
  return d;
}

double particle_radius(const FillOptions& o, double volume, double area) {
  if (o.radii) {
    const auto d = fill_sizes(o, volume, area);
    return d && volume > 0 ? d->mean() : 0;
  }
  return o.radius > 0 ? o.radius : fill_radius_for_count(volume, area, o.count, o.max_overlap, o.rest_distance);
}

FillPlan plan_fill(const Box3& bounds, const MeshDiagnostics& d, const FillOptions& o, double size_scale) {
  FillPlan plan;
  plan.volume = d.volume();
  plan.area = d.surface_area;
  if (!(plan.volume > 0)) throw Error("the mesh encloses no volume; pfill needs a closed solid");
  plan.sizes = fill_sizes(o, plan.volume, plan.area);
  plan.radius = plan.sizes ? plan.sizes->min_radius() : particle_radius(o, plan.volume, plan.area);
  if (!(plan.radius > 0)) throw Error("give a particle radius (-r) or a count (-n)");
  plan.mean_radius = plan.sizes ? plan.sizes->mean() : plan.radius;
  plan.max_radius = plan.sizes ? plan.sizes->max_radius() : plan.radius;
  plan.expected = plan.sizes ? expected_fill_count(plan.volume, plan.area, *plan.sizes, o.max_overlap)
                             : expected_fill_count(plan.volume, plan.area, plan.radius * o.rest_distance,
                                                   o.max_overlap, o.rest_distance);
  if (plan.expected > kMaxParticles)
    throw Error("a radius of " + short_number(plan.radius) + " would give about " + short_number(plan.expected) +
                " particles, more than pfill handles (" + short_number(kMaxParticles) +
                "); choose a larger radius or a smaller count");
  if (plan.sizes && size_scale != 1) {  // (the count stays the count rule's at the scale asked)
    plan.sizes = plan.sizes->scaled(size_scale);
    plan.radius = plan.sizes->min_radius();
    plan.mean_radius = plan.sizes->mean();
    plan.max_radius = plan.sizes->max_radius();
    plan.size_scale = size_scale;
  }

  // The field: at a share of r, coarsened to stay within max_field_samples.
  SdfOptions& so = plan.field;
  so.spacing = o.field_spacing * plan.mean_radius;
  const Vec3 size = bounds.size();
  const double margin = 3 * so.spacing + 2 * plan.mean_radius + (plan.max_radius - plan.mean_radius);
  auto samples = [&](double h) {
    return (size.x + 2 * margin) / h * (size.y + 2 * margin) / h * (size.z + 2 * margin) / h;
  };
  if (samples(so.spacing) > static_cast<double>(o.max_field_samples)) {
    so.spacing *= std::cbrt(samples(so.spacing) / static_cast<double>(o.max_field_samples)) * 1.01;
    plan.warnings.push_back("the distance field was coarsened to a spacing of " + short_number(so.spacing / plan.mean_radius) +
                            " r to stay within " + short_number(static_cast<double>(o.max_field_samples)) +
                            " samples; the final exact check corrects what it misses");
  }
  so.margin = 2 * plan.mean_radius + (plan.max_radius - plan.mean_radius) + 3 * so.spacing;
  // Exact distances only where the fill reads them (issue 32; farther in,
  // values are interpolated from a coarser level of exact ones, at least
  // the band deep, so the deepest point is still an exact sample): inside,
  // the wall acts on centres within r (1 + wall_margin) of the surface and
  // samples corners up to a cell diagonal beyond that; holes need depth r;
  // wave sites need depth site_min_depth r (2 r by default), which values
  // at least the band deep prove. Outside, the wall reads the corners of
  // a centre's cell, up to a cell diagonal (1.73 spacings) beyond the
  // surface; farther out only the sign matters (a centre there is flagged
  // and removed), so 2 spacings (tests/test_fill_plan.cpp checks the
  // corners). (Was max(3 r, 4 spacings) on both sides: the bunny at -n
  // 4000 made 1.21 million exact queries; 0.68 million with 4 spacings
  // outside, 0.54 million with 2, the same fills to the byte.) Unequal
  // spheres: the wall pushes each at its own radius, so the band reaches
  // past the largest's.
  so.band = std::max({2 * plan.mean_radius, plan.max_radius + 2 * so.spacing, 4 * so.spacing});
  so.outer_band = 2 * so.spacing;
  // Deeper in, exact values every 4 spacings (0.3% more queries): the
  // deepest point, where sites start, within about a radius (the octree's
  // coarsest lattice, 16 spacings, had the bunny's 7% short).
  so.inside_cell = 4;

  plan.waves = o.sites == 0 || (o.sites < 0 && std::llround(plan.expected) >= static_cast<long long>(kWavesFrom));
  plan.time_step = o.time_step > 0 ? o.time_step : plan.waves && !plan.sizes ? kWaveTimeStep : kSiteTimeStep;
  plan.max_step = o.max_step > 0 ? o.max_step : std::min(0.5, kTopSpeed * plan.time_step);
  plan.birth_every =
      o.birth_every > 0 ? o.birth_every : (plan.waves ? static_cast<int>(std::lround(kWaveEveryTau / plan.time_step)) : 3);
  plan.birth_every = std::max(1, plan.birth_every);
  plan.patience = o.patience > 0 ? o.patience
                                 : std::max({100, 10 * plan.birth_every,
                                             static_cast<int>(std::lround(kPatienceTau / plan.time_step))});
  plan.birth_clearance = o.birth_clearance > 0 ? o.birth_clearance : (plan.waves ? kWaveClearance : kSiteClearance);
  return plan;
}

std::vector<BirthSite> plan_birth_sites(const FillPlan& plan, const ScalarGrid& field, const Boundary& boundary,
                                        const FillOptions& o) {
  std::vector<BirthSite> sites;
  // (Unequal spheres: sites spaced and as deep as for spheres of the mean radius.)
  if (plan.waves)
    sites = spread_birth_sites(field, o.site_spacing * plan.mean_rest_distance(o), o.site_min_depth * plan.mean_radius);
  if (sites.empty())  // the report's sites; for waves, the one deepest point of a thin object
    sites = choose_birth_sites(field, report_site_count(o), plan.mean_radius, o.site_depth);
  if (sites.empty()) {
    double deepest = 0;
    for (float v : field.values) deepest = std::max(deepest, -static_cast<double>(v));
    throw Error("no particle of radius " + short_number(plan.radius) + " fits: the deepest point is " + short_number(deepest) +
                " from the surface; choose a smaller radius or a larger count");
  }
  put_given_birth(sites, plan, boundary, o);
  return sites;
}

BirthSite given_birth_site(const FillPlan& plan, const Boundary& boundary, const FillOptions& o) {
  const Vec3 p = o.birth.value_or(Vec3());
  if (!boundary.inside(p)) throw Error("birth is outside the mesh; give a point inside it or leave it out");
  const double depth = -boundary.signed_distance(p);
  if (depth < plan.radius)
    throw Error("birth is only " + short_number(depth) + " from the surface, less than the radius " +
                short_number(plan.radius) + "; move it deeper inside");
  return {p, depth};
}

void put_given_birth(std::vector<BirthSite>& sites, const FillPlan& plan, const Boundary& boundary,
                     const FillOptions& o) {
  if (o.birth && !sites.empty()) sites[0] = given_birth_site(plan, boundary, o);
}

EngineParams plan_engine_params(const FillPlan& plan, const FillOptions& o) {
  EngineParams p;
  p.radius = plan.radius;
  p.max_radius = plan.max_radius * (1 + 1e-6);  // radii come back from the device as floats
  // Unequal spheres: each pair's sigma, cutoff and rest distance scale with r_i + r_j.
  if (plan.sizes) p.pair_scaling = PairScaling::on;
  p.rest_distance = plan.rest_distance(o);
  p.eps = o.epsilon;
  p.exponent_a = o.exponents[0];
  p.exponent_b = o.exponents[1];
  p.cutoff_sigma = o.cutoff;
  p.restitution = o.restitution;
  p.wall_restitution = o.wall_restitution;
  p.damping = o.damping;
  p.dt = plan.time_step * derive_constants(p).tau;
  p.max_step_fraction = plan.max_step;
  p.skin_sigma = o.skin;
  p.births_at_speed = true;
  return p;
}

void check_device_memory(const Device& device, const FillPlan& plan, size_t field_bytes) {
  const double needed = plan.expected * kDeviceBytesPerParticle + kDeviceBytesFixed + static_cast<double>(field_bytes);
  const double has = static_cast<double>(device.info().global_memory);
  if (has > 0 && needed > has)
    throw Error("about " + short_number(plan.expected) + " particles need ~" + short_number(needed / 1048576.0) + " MiB but " +
                device.info().name + " has " + short_number(has / 1048576.0) +
                " MiB; choose a larger radius or another device (--device)");
}

}  // namespace pfill
