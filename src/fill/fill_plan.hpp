// The plan of a fill, made before any step: the radius (from -r or the
// count rule), the count expected, the distance field's spacing, the birth
// schedule and its sites, the engine's settings, and whether the device
// holds it all.
#pragma once
#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "pfill/birth_sites.hpp"
#include "pfill/engine/params.hpp"
#include "pfill/fill.hpp"
#include "pfill/mesh_diagnostics.hpp"
#include "pfill/sdf.hpp"

namespace pfill {

class Boundary;
class Device;

// Pass 1's time step, in tau: waves of equal spheres take steps twice the
// report's. With the top speed, the time between waves and the patience
// held the same in tau, their pass 1 takes half the steps and packs as
// densely (spot -n 4000 seeds 1-12 0.6009 against 0.6010, 16,000 and 1e5
// denser; docs/benchmarks.md, 2026-12-06). Alone, a doubled step halves
// the top speed and fills short (0.5812); at 0.03 tau births jam. Unequal
// spheres keep the report's step: lognormal radii lost 0.008 at twice it.
constexpr double kWaveTimeStep = 0.02, kSiteTimeStep = 0.01;

struct FillPlan {
  double volume = 0;          ///< of the mesh (or the union of its parts)
  double area = 0;            ///< of its surface
  double radius = 0;          ///< of every sphere; unequal spheres: the smallest (the engine's reference)
  /// Unequal spheres: the radii's distribution in mesh units; empty: all `radius`.
  std::optional<RadiusDistribution> sizes;
  double mean_radius = 0;     ///< by number; sets the field's spacing and the sites' (equal: radius)
  double max_radius = 0;      ///< the largest sphere (equal: radius)
  double expected = 0;        ///< particles when full, by the count rule
  /// Unequal spheres: every radius shrunk by this after the count rule, so
  /// that the rare large ones fit (large_first_scale.hpp); 1: as the rule says.
  double size_scale = 1;
  SdfOptions field{0};        ///< the distance field's spacing, margin and band
  bool waves = false;         ///< births in waves over spread sites (else the report's sites)
  double time_step = kSiteTimeStep;  ///< pass 1's step, in tau (FillOptions::time_step, or the schedule's)
  double max_step = 0.1;      ///< a step's largest move, in sigma (the top speed)
  int birth_every = 3;        ///< steps between births at a site (a wave's steps with waves)
  int patience = 1500;        ///< steps with no birth (waves: few births) that end pass 1
  double birth_clearance = 0.5;  ///< room test radius, in rest distances
  std::vector<std::string> warnings;  ///< what the plan had to give up (a coarsened field)

  /// Centre distance at the potential's minimum: 2r, or more for sparser
  /// fills (unequal spheres: of two of the smallest; each pair's scales).
  double rest_distance(const FillOptions& o) const { return o.rest_distance * 2 * radius; }
  /// The same for two spheres of the mean radius: what sites are spaced by.
  double mean_rest_distance(const FillOptions& o) const { return o.rest_distance * 2 * mean_radius; }
};

/// The radius of a fill: -r, or the one that gives about -n particles.
/// Particles keep the rest distance apart, so with a count the spacing, not
/// the sphere, is what must fit (the report's Fig. 4). Unequal spheres:
/// the mean radius of fill_sizes().
double particle_radius(const FillOptions& o, double volume, double area);

/// Unequal spheres: FillOptions::radii in mesh units (scaled to the count
/// when one is given); empty for equal spheres.
std::optional<RadiusDistribution> fill_sizes(const FillOptions& o, double volume, double area);

/// Radius, expected count, field and schedule for `o` on a mesh of box
/// `bounds` and diagnostics `d` (`o` checked: check_fill_options); throws
/// when they cannot work. Unequal spheres: `size_scale` shrinks every
/// radius after the count rule, which the expected count keeps
/// (large_first_scale.hpp: the large spheres' quota then fits).
FillPlan plan_fill(const Box3& bounds, const MeshDiagnostics& d, const FillOptions& o, double size_scale = 1);

/// The birth sites of the plan's schedule on `field`: spread over the inside
/// for waves, else the report's deepest far-apart points; FillOptions::
/// birth_point replaces the first. Throws when no sphere fits.
std::vector<BirthSite> plan_birth_sites(const FillPlan& plan, const ScalarGrid& field, const Boundary& boundary,
                                        const FillOptions& o);

/// How many sites the report's schedule asks (FillOptions::sites; 2 when left to pfill).
inline int report_site_count(const FillOptions& o) { return o.sites < 0 ? 2 : std::max(1, o.sites); }

/// FillOptions::birth as a site at its exact depth; throws when it is
/// outside the mesh or less than a radius inside.
BirthSite given_birth_site(const FillPlan& plan, const Boundary& boundary, const FillOptions& o);

/// FillOptions::birth in place of the first of `sites` (given_birth_site).
void put_given_birth(std::vector<BirthSite>& sites, const FillPlan& plan, const Boundary& boundary,
                     const FillOptions& o);

/// The engine's settings for passes 1 to 3: the report's physics in the
/// units of the plan's radius.
EngineParams plan_engine_params(const FillPlan& plan, const FillOptions& o);

/// Throws when the particles expected and the field will not fit in the
/// device's memory.
void check_device_memory(const Device& device, const FillPlan& plan, size_t field_bytes);

}  // namespace pfill
