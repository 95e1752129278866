// The plan, the field and the birth sites of a fill (FillRun, fill_run.hpp):
// on the field, or where no process builds one (the LAMMPS engine) from
// the mesh, each process choosing the sites of its own sub-domain or the
// report's few sites from the candidates it holds; the rare large spheres'
// scale and placement on the same (large_first.hpp), and a site for each
// of the mesh's closed parts that has none (part_sites.hpp).
#include <algorithm>
#include <memory>
#include <optional>
#include <vector>

#include "fill/fill_run.hpp"
#include "fill/large_first.hpp"
#include "fill/large_first_scale.hpp"
#include "fill/mesh_parts.hpp"
#include "fill/mesh_sites.hpp"
#include "fill/part_sites.hpp"
#include "fill/short_number.hpp"
#include "fill/site_choice.hpp"
#include "pfill/birth_sites.hpp"
#include "pfill/sdf.hpp"

namespace pfill {
namespace {

// Room sites (FillOptions::room_spacing) lie at least this many radii
// inside: a newborn there starts clear of the wall as of every sphere.
constexpr double kRoomSiteDepth = 1.2;
// The large spheres' candidates (sites from the mesh) reach a little
// shallower than the smallest scale large_first_scale tries needs.
constexpr double kBelowLowestScale = 0.99;

}  // namespace

bool FillRun::sites_from_mesh() const {
  return o_.engine && o_.wall_from_mesh;
}

SdfOptions FillRun::coarse_options() const {
  SdfOptions coarse = plan_.field;
  coarse.spacing *= 2;
  return coarse;
}

void FillRun::choose_split_sites(const SdfOptions& coarse) {
  if (plan_.waves ? split_wave_sites() : report_sites_from_mesh()) return;
  field_ = build_signed_distance_field(*boundary_, coarse);
  plan_sites();
}

bool FillRun::split_wave_sites() {
  const SiteLattice waves(mesh_.bounds(), o_.site_spacing * plan_.mean_rest_distance(o_),
                          o_.site_min_depth * plan_.mean_radius);
  std::optional<SiteLattice> rooms;
  if (o_.room_spacing > 0 && !plan_.sizes)
    rooms.emplace(mesh_.bounds(), o_.room_spacing * plan_.rest_distance(o_), kRoomSiteDepth * plan_.radius);
  const BirthView view = engine_->birth_view(0, false);
  held_ = split_sites(*boundary_, waves, rooms, *engine_, view);
  if (held_.total_sites == 0) return false;
  if (o_.birth) put_given_site(held_, given_birth_site(plan_, *boundary_, o_), *engine_, view);
  if (diagnostics_.components > 1) {
    const HeldCandidates candidates =
        mesh_candidates(*boundary_, mesh_.bounds(), coarse_options().spacing, plan_.radius, view);
    for (const KeyedSite& k : sites_for_parts(held_.sites, candidates)) {
      ++held_.total_sites;
      if (!view.decides(k.site.position)) continue;
      held_.sites.push_back(k.site);  // (the parts' keys come after every lattice index: still in key order)
      held_.keys.push_back(k.key);
    }
  }
  return true;
}

bool FillRun::report_sites_from_mesh() {
  const HeldCandidates held = mesh_candidates(*boundary_, mesh_.bounds(), coarse_options().spacing,
                                              plan_.mean_radius, engine_->birth_view(0, false));
  sites_ = choose_birth_sites(held, report_site_count(o_), plan_.mean_radius, o_.site_depth,
                              *engine_->process_group());
  if (sites_.empty()) return false;
  put_given_birth(sites_, plan_, *boundary_, o_);
  if (diagnostics_.components > 1)
    for (const KeyedSite& k : sites_for_parts(sites_, held)) sites_.push_back(k.site);
  held_ = replicated_sites(sites_, {});
  return true;
}

void FillRun::plan_sites() {
  sites_ = plan_birth_sites(plan_, field_, *boundary_, o_);
  if (diagnostics_.components > 1)  // every closed part that can hold a sphere gets a site
    note_parts(add_sites_per_part(field_, plan_.radius, sites_));
  // (Unequal spheres: the waves' sites alone.)
  std::vector<BirthSite> room_sites;
  if (plan_.waves && o_.room_spacing > 0 && !plan_.sizes)
    room_sites = spread_birth_sites(field_, o_.room_spacing * plan_.rest_distance(o_), kRoomSiteDepth * plan_.radius);
  held_ = replicated_sites(sites_, std::move(room_sites));
}

std::vector<KeyedSite> FillRun::sites_for_parts(const std::vector<BirthSite>& sites,
                                                const HeldCandidates& candidates) {
  const PartSiteChoice parts =
      sites_for_empty_parts(MeshParts(*boundary_), sites, candidates, plan_.radius, *engine_->process_group());
  note_parts(parts.counts);
  return parts.added;
}

void FillRun::note_parts(const PartSites& parts) {
  result_.parts = parts.parts;
  result_.parts_too_small = parts.too_small;
  if (parts.too_small == 0) return;
  const std::string warning = std::to_string(parts.too_small) + " of the mesh's " + std::to_string(parts.parts) +
                              " closed parts are too small for a sphere of radius " + short_number(plan_.radius) +
                              " and stay empty";
  std::vector<std::string>& w = result_.warnings;
  if (std::find(w.begin(), w.end(), warning) == w.end()) w.push_back(warning);  // (once: a new scale plans again)
}

void FillRun::rescale_for_large_first() {
  if (!plan_.sizes || o_.count == 0) return;  // radii in mesh units (no count) are the user's: kept
  const double scale = large_first_scale(large_placer(), plan_, held_.total_sites, o_.seed);
  if (scale != 1) replan_at(scale);
}

void FillRun::rescale_split() {
  if (!plan_.sizes) return;
  if (!field_.values.empty()) return rescale_for_large_first();  // (an object too thin for the lattice's sites)
  const std::vector<double> radii = front_loaded_radii(plan_, held_.total_sites, o_.seed);
  if (radii.empty() || o_.count == 0) return;  // (no count: the placement's own candidates)
  const double lowest = kBelowLowestScale * lowest_large_first_scale();
  candidates_ = held_candidates(*std::min_element(radii.begin(), radii.end()) * lowest,
                                large_first_settings(lowest * plan_.radius));
  const double scale = large_first_scale(large_placer(), plan_, held_.total_sites, o_.seed);
  if (scale != 1) replan_at(scale);
}

void FillRun::replan_at(double scale) {
  const SdfOptions field = plan_.field;
  plan_ = plan_fill(mesh_.bounds(), diagnostics_, o_, scale);
  plan_.field = field;
  result_.radius = plan_.radius;
  if (!engine_) return plan_sites();
  engine_.reset();
  make_engine();
  if (field_.values.empty())
    choose_split_sites(coarse_options());
  else
    plan_sites();
}

HeldCandidates FillRun::held_candidates(double smallest, const LargeFirstSettings& s) {
  return mesh_candidates(*boundary_, mesh_.bounds(), coarse_options().spacing, smallest + s.wall_gap,
                         engine_->birth_view(0, false));
}

LargePlacer FillRun::large_placer() {
  if (!field_.values.empty())
    return [this](const std::vector<double>& radii, const LargeFirstSettings& s) {
      return place_large_first(field_, radii, s);
    };
  return [this](const std::vector<double>& radii, const LargeFirstSettings& s) {
    if (!candidates_) candidates_ = held_candidates(*std::min_element(radii.begin(), radii.end()), s);
    const std::shared_ptr<ProcessGroup> group = engine_->process_group();
    return place_large_first(*candidates_, radii, s, *group);
  };
}

}  // namespace pfill
