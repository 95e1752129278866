// The fill, read top-down as the algorithm of DESIGN.md:
//
//   plan:    radius (from -r or the count rule), field spacing, schedule (fill_plan.cpp)
//   field:   mesh -> boundary -> signed distance field -> birth sites -> engine
//            (fill_sites.cpp; FillRun in fill_run.hpp)
//   pass 1:  while not overfull: births at the sites; update      (fill_passes.cpp)
//   pass 2:  MaxParts = count - 1; top up to MaxParts
//   settle:  update until at rest
//   finish:  relax overlaps away by moving spheres; delete only where that
//            stalls over the bound; fill holes                     (finish.cpp)
//   verify:  exact containment repair, holes, metrics, colours    (fill_verify.cpp)
#include "pfill/fill.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <future>
#include <limits>
#include <memory>
#include <optional>

#include "fill/fill_options_check.hpp"
#include "fill/fill_passes.hpp"
#include "fill/fill_plan.hpp"
#include "fill/fill_run.hpp"
#include "fill/fill_progress.hpp"
#include "fill/fill_verify.hpp"
#include "fill/finish.hpp"
#include "fill/held_sites.hpp"
#include "fill/particle_set_of.hpp"
#include "pfill/boundary.hpp"
#include "pfill/device/device.hpp"
#include "pfill/engine/engine.hpp"
#include "pfill/engine/local_view.hpp"
#include "pfill/error.hpp"
#include "pfill/exact_field.hpp"
#include "pfill/mesh_diagnostics.hpp"
#include "pfill/particle_share.hpp"
#include "pfill/peak_memory.hpp"
#include "pfill/sdf.hpp"
#include "fill/short_number.hpp"
#include "fill/stopwatch.hpp"

namespace pfill {
namespace {

// Holes the finish compresses a loose packing at (FinishSettings::
// compress_clearance), in r: the closed bunny, the report's schedule with
// attraction, -n 4000: 0.5818 at the 0.1% bound and 0.6086 at 5% (1.9 r:
// 0.466 / 0.526); 1.5 r deleted a third of what it inserted.
constexpr double kCompressClearance = 1.7;

// PFILL_PROFILE=1 (any value but empty or 0): the fill's queue profiles
// every command, and each pass reports its kernel and transfer time.
bool profile_requested() {
  const char* v = std::getenv("PFILL_PROFILE");
  return v && *v && std::string(v) != "0";
}

}  // namespace

FillResult FillRun::run() {
  prepare();
  note_device_times();
  FillPasses passes(*engine_, o_, plan_, std::move(held_), reporter_, result_);
  passes.place_large_first(large_placer());
  candidates_.reset();
  // With the wall from the mesh, the field's samples served the sites
  // only: the finish's holes ask the mesh (its grid, kept, lays them out).
  if (wall_) std::vector<float>().swap(field_.values);
  size_caps_ = passes.size_caps();
  result_.setup_seconds = std::max(0.0, reporter_.elapsed() - result_.field_seconds);
  passes.pass1();
  note_device_times();
  passes.pass2();
  note_device_times();
  passes.settle();
  note_device_times();
  if (o_.engine)  // (another engine's records do not say when it rebuilt its lists)
    for (PassStats& p : result_.passes) p.list_rebuilds = -1;
  result_.sites = passes.all_sites();
  finish(passes.next_id());
  note_device_times();
  verify();
  if (!size_caps_.empty()) result_.warnings.push_back(held_to_large_note(passes.short_front()));
  return std::move(result_);
}

std::string FillRun::held_to_large_note(const std::string& short_front) const {
  std::string what = plan_.size_scale < 1 ? "every radius was scaled by " + short_number(plan_.size_scale) +
                                                " for the largest spheres to fit"
                                          : std::string();
  if (!short_front.empty()) what += (what.empty() ? "" : ", and even so ") + short_front;
  return what + ": the other classes were held to their shares of them, " +
         std::to_string(result_.metrics.count) + " spheres at a packing of " +
         short_number(result_.metrics.packing_fraction);
}

void FillRun::note_device_times() {
  if (!device_ || !device_->profiling()) return;
  const DeviceTimes now = device_->times();
  if (device_times_noted_ && !result_.passes.empty()) {
    result_.passes.back().kernel_seconds = now.kernel_seconds - device_times_.kernel_seconds;
    result_.passes.back().transfer_seconds = now.transfer_seconds - device_times_.transfer_seconds;
    for (const auto& [name, seconds] : now.by_kernel) {
      const auto before = device_times_.by_kernel.find(name);
      const double pass = seconds - (before == device_times_.by_kernel.end() ? 0.0 : before->second);
      if (pass > 0) result_.passes.back().kernel_split[name] = pass;
    }
  }
  device_times_ = now;
  device_times_noted_ = true;
}

void FillRun::prepare() {
  check_fill_options(o_);  // a bad setting is the first thing to say
  if (!(diagnostics_.volume() > 0))
    throw Error(mesh_.source + ": the mesh encloses no volume; pfill needs a closed solid");
  plan_ = plan_fill(mesh_.bounds(), diagnostics_, o_);
  check_fill_options(o_, mesh_, plan_.radius);
  if (diagnostics_.boundary_edges > 0)
    result_.warnings.push_back("the mesh is open (" + std::to_string(diagnostics_.boundary_loops) +
                               " holes): inside is decided by a majority of rays; particles near the holes may "
                               "be removed by the final check");
  if (diagnostics_.inside_out()) {
    flip_orientation(mesh_);
    result_.warnings.push_back("the mesh was inside-out (negative volume): its orientation was reversed");
  }
  result_.radius = plan_.radius;
  result_.expected = static_cast<size_t>(std::llround(plan_.expected));
  result_.warnings.insert(result_.warnings.end(), plan_.warnings.begin(), plan_.warnings.end());

  reporter_.enter(FillPhase::Field);
  reporter_.report(0, 0, 0, 0, 0);
  // The device opens beside the Embree scene and the field (PoCL loads
  // LLVM and starts its threads: ~0.15-0.25 s); its errors come after the field's, as before.
  std::future<std::unique_ptr<Device>> device;
  if (!o_.engine)
    device = std::async(std::launch::async, [this] { return std::make_unique<Device>(o_.device, profile_requested()); });
  boundary_ = std::make_unique<Boundary>(mesh_);
  SdfStats stats;
  if (o_.engine && o_.wall_from_mesh) {
    // The engine's wall from the mesh, at the planned spacing; the fill's
    // sites and holes on a field twice as coarse.
    wall_ = std::make_unique<ExactField>(*boundary_, plan_.field);
    const SdfOptions coarse = coarse_options();
    // Sites split over the processes come from the mesh: the grid only lays out the finish's holes.
    field_ = sites_from_mesh() ? sdf_lattice(mesh_.bounds(), coarse) : build_signed_distance_field(*boundary_, coarse, &stats);
  } else {
    field_ = build_signed_distance_field(*boundary_, plan_.field, &stats);
  }
  throw_if_cancelled();  // the field can take seconds; the device's program build too
  result_.field_seconds = stats.seconds;
  result_.field_bytes = stats.bytes;
  result_.field_spacing = field_.spacing;
  if (!sites_from_mesh()) {
    plan_sites();
    rescale_for_large_first();
  }

  if (device.valid()) device_ = device.get();
  result_.device = device_ ? device_->info().name : std::string("none (FillOptions::engine)");
  if (device_) check_device_memory(*device_, plan_, stats.bytes);
  make_engine();
  if (o_.log) o_.log(engine_->describe());
  if (!sites_from_mesh()) return;
  choose_split_sites(coarse_options());
  rescale_split();
}

void FillRun::make_engine() {
  params_ = plan_engine_params(plan_, o_);
  engine_ = o_.engine ? o_.engine(params_) : std::make_unique<Engine>(*device_, params_);
  if (wall_)
    engine_->share_exact_field(*wall_);
  else
    engine_->share_field(field_);  // on PoCL read in place (field_ outlives engine_)
}

void FillRun::finish(uint64_t next_id) {
  const Stopwatch t;
  reporter_.enter(FillPhase::Finish);
  reporter_.time_left().finish_started(reporter_.elapsed());
  fill_steps_ = engine_->steps_done();
  next_id_ = next_id;
  if (!device_ && !o_.finish_on_engine) {  // FillOptions::engine: no OpenCL engine for the finish
    particles_ = to_particle_set(engine_->read_particles());
    engine_.reset();
    result_.warnings.push_back("the finish was left out: it needs the OpenCL engine (FillOptions::engine was given)");
    return;
  }
  // Each process hands the finish its own particles (one process: all);
  // split over processes, at places in process order (SetShare).
  LocalView handed = engine_->local_view(0);
  std::vector<Particle> ps = std::move(handed.particles);
  ps.resize(handed.own);
  const SetShare share =
      handed.complete() ? SetShare{} : share_over_processes(*engine_, ps.size(), handed.region, false);
  // (the verify reaches the other processes through it once the engines are gone)
  std::shared_ptr<ProcessGroup> group = engine_->process_group();
  engine_.reset();  // the finish holds the particles from here on
  reporter_.report(share.total == 0 ? ps.size() : share.total, 0, 0, fill_steps_, 0);  // the phase starts (progress lines, time left)
  FinishStats stats;
  auto progress = [&](size_t n, uint32_t pairs) {
    relax_steps_ = stats.steps;  // the finish's steps so far, for the progress line
    reporter_.report(n, 0, pairs, fill_steps_ + relax_steps_, relax_steps_);
  };
  particles_ = device_ ? finish_packing(*device_, params_, field_, std::move(ps), finish_settings(), stats, progress)
                       : finish_packing(o_.engine, params_, field_, std::move(ps), share, finish_settings(), stats,
                                        progress);
  relax_steps_ = stats.steps;
  field_ = ScalarGrid();  // (memory: up to 256 MiB) nothing after the finish samples the field
  wall_.reset();
  result_.finish_removed = stats.removed;
  result_.finish_forced = stats.forced;
  result_.finish_rounds = stats.rounds;
  result_.finish_near_rounds = stats.near_rounds;
  result_.finish_largest_view = stats.largest_view;
  result_.holes_filled = stats.inserted;
  if (!stats.regions.empty()) {  // the result in parts: this process's own spheres (particle_share.hpp)
    share_.group = std::move(group);
    share_.regions = std::move(stats.regions);
    share_.region = stats.region;
    result_.in_parts = true;
  }
  next_id_ = stats.next_id;
  result_.passes.push_back({to_string(FillPhase::Finish), stats.steps, t.seconds()});
}

FinishSettings FillRun::finish_settings() const {
  FinishSettings s;
  s.radius = plan_.radius;
  s.sizes = plan_.sizes;
  s.size_caps = size_caps_;
  s.max_overlap = o_.max_overlap;
  s.hole_rounds = o_.hole_rounds;
  s.hole_clearance = o_.hole_clearance * 2 * o_.rest_distance;
  // The report's own tests end pass 1 before the object is full (at about
  // 60% of the count on the bunny with attraction): the finish compresses
  // what they left. The blocked-sites test ends it full.
  if (o_.hole_rounds > 0 && (result_.stop_signal == to_string(StopCriterion::KineticEnergy) ||
                             result_.stop_signal == to_string(StopCriterion::Collisions)))
    s.compress_clearance = kCompressClearance * o_.rest_distance;
  s.fit_clearance = 2 * o_.rest_distance;
  // FIRE runs on the OpenCL engine and on LAMMPS (finish_on_engine), for
  // equal spheres, and not while compressing: it made room
  // so well that the bunny's compression ran all 30 rounds, and a
  // lognormal mix of radii ran out of rounds too (docs/finish.md, FIRE);
  // with each pair's energy by its volume (eps q^3) FIRE still ends
  // below the damped relaxation for mixtures (docs/polydisperse.md).
  s.fire = (device_ != nullptr || o_.finish_on_engine) && s.compress_clearance == 0 && !plan_.sizes;
  s.first_id = next_id_;
  s.cancelled = o_.cancelled;
  s.wall = wall_.get();
  return s;
}

void FillRun::verify() {
  const Stopwatch t;
  reporter_.enter(FillPhase::Verify);
  const size_t count = static_cast<size_t>(share_.group->sum(static_cast<double>(particles_.size())));
  reporter_.report(count, 0, 0, fill_steps_ + relax_steps_, relax_steps_);
  verify_fill(*boundary_, mesh_, plan_.volume, plan_.radius, plan_.sizes, size_caps_, o_, std::move(particles_), share_,
              next_id_, result_);
  result_.verify_seconds = t.seconds();
  result_.seconds = reporter_.elapsed();
  result_.steps = fill_steps_ + relax_steps_;
  result_.peak_memory = peak_resident_bytes();
}

void FillRun::throw_if_cancelled() const {
  if (o_.cancelled && o_.cancelled()) throw Cancelled();
}


namespace {

// "No particle fits", with the mesh's depth measured on a field of 64
// samples across, and the way out that fits the options given.
std::string no_room_message(const Mesh& mesh, double volume, double area, const FillOptions& o) {
  const double radius = particle_radius(o, volume, area);
  const Boundary boundary(mesh);
  SdfOptions so(spacing_for_resolution(mesh.bounds(), 64));
  so.band = std::numeric_limits<double>::infinity();
  const ScalarGrid field = build_signed_distance_field(boundary, so);
  double deepest = 0;
  for (float v : field.values) deepest = std::max(deepest, -static_cast<double>(v));
  return "no particle of radius " + short_number(radius) + " fits: the deepest point is about " + short_number(deepest) +
         " from the surface; " +
         (o.radius > 0 ? "choose a radius below " + short_number(deepest) : std::string("ask for more particles (-n)"));
}

// A mesh whose box the distance field cannot cover at a spacing near the
// radius (a stray vertex far from the rest makes one) would build a field
// of billions of samples or fill nothing: say which vertex lies farthest
// from the median of all, and stop.
void refuse_stray_vertices(const Mesh& mesh, double volume, double area, const FillOptions& o) {
  const double radius = particle_radius(o, volume, area);
  if (!(radius > 0) || mesh.positions.empty()) return;
  check_coordinates_resolve(mesh, radius);  // far out, doubles cannot hold the fill
  // Too many particles is the first thing to say (the run's check says it).
  const double half_rest = radius * o.rest_distance;
  if (o.count > kMaxParticles || expected_fill_count(volume, area, half_rest, o.max_overlap, o.rest_distance) > kMaxParticles)
    return;
  const Vec3 size = mesh.bounds().size();
  const double spacing = o.field_spacing * radius, margin = 2 * radius + 3 * spacing;
  const double samples = (size.x + 2 * margin) / spacing * ((size.y + 2 * margin) / spacing) *
                         ((size.z + 2 * margin) / spacing);
  constexpr double kMostCoarsening = 8;  // the field may be coarsened, but not to several radii
  if (!(samples > std::pow(kMostCoarsening, 3) * static_cast<double>(o.max_field_samples))) return;
  Vec3 median;
  for (int a = 0; a < 3; ++a) {
    std::vector<double> values;
    for (const Vec3& p : mesh.positions) values.push_back(p[a]);
    std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
    median[a] = values[values.size() / 2];
  }
  size_t stray = 0;
  for (size_t i = 0; i < mesh.positions.size(); ++i)
    if (length(mesh.positions[i] - median) > length(mesh.positions[stray] - median)) stray = i;
  const Vec3& p = mesh.positions[stray];
  throw Error((mesh.source.empty() ? std::string("the mesh") : mesh.source) + ": its box (" + short_number(size.x) + " x " +
              short_number(size.y) + " x " + short_number(size.z) + ") is too large for particles of radius " + short_number(radius) +
              " (a volume of " + short_number(volume) + "): is the vertex at (" + short_number(p.x) + ", " + short_number(p.y) + ", " + short_number(p.z) +
              ") a stray? remove it, or choose a larger radius");
}

}  // namespace

FillResult fill(const Mesh& mesh, const FillOptions& options) {
  // The engine holds positions in single precision: far from the origin
  // they would lose their digits (spot moved by 1e6 filled at a packing of
  // 0.28). The run works in coordinates centred on the mesh's box, and
  // everything it returns is moved back into the mesh's own.
  const Vec3 centre = mesh.bounds().centre();
  Mesh local = mesh;
  for (Vec3& p : local.positions) p -= centre;
  remove_duplicate_triangles(local);  // a repeated face would count twice along a ray
  orient_faces(local);                // inconsistent winding would give a wrong volume (load_mesh does it too)
  FillOptions o = options;
  if (o.birth) o.birth = *o.birth - centre;
  if (options.on_frame)
    o.on_frame = [&options, centre](uint64_t step, const ParticleSet& s) {
      ParticleSet moved = s;
      for (Vec3& p : moved.positions) p += centre;
      options.on_frame(step, moved);
    };
  const MeshDiagnostics d = diagnose(local);  // once: the winding-number sweep takes a while on big meshes
  refuse_stray_vertices(mesh, d.volume(), d.surface_area, options);
  FillRun run(local, d, o);
  FillResult result;
  try {
    result = run.run();
  } catch (const Error& e) {
    // The run's field is as coarse as the radius is large: measure the
    // depth on a fine field before saying that no particle fits.
    if (std::string(e.what()).rfind("no particle of radius", 0) != 0) throw;
    throw Error(no_room_message(local, d.volume(), d.surface_area, o));
  }
  for (Vec3& p : result.particles.positions) p += centre;
  for (BirthSite& site : result.sites) site.position += centre;

  const std::string name = mesh.source.empty() ? std::string("the mesh") : mesh.source;
  if (d.overlapping())
    result.warnings.push_back(
        std::string(d.components > 1 ? "parts of the mesh intersect or lie inside one another"
                                     : "the surface intersects itself") +
        ": filled as the union of what it encloses (inside = a non-zero winding number); the volume " + short_number(d.volume()) +
        " is the union's, estimated by rays" +
        (d.components > 1 ? "" : ", and its inner surfaces act as walls; repair the mesh for a clean fill"));

  // A fill that ends empty or far short of its estimate is not a result.
  if (result.particles.size() == 0)
    throw Error(name + ": the fill ended with no particles (" + std::to_string(result.lost_outside) +
                " left through the surface); check the mesh with `pfill info` (open, self-intersecting or "
                "too thin for the radius?)");
  if (result.expected > 0 && result.particles.size() * 4 < result.expected)
    result.warnings.push_back("only " + std::to_string(result.particles.size()) + " particles of the ~" +
                              std::to_string(result.expected) + " expected: " +
                              (result.stop_signal == "budget"
                                   ? std::string("pass 1 ran out of its step budget (max_steps ") +
                                         std::to_string(o.max_steps) + "); allow more steps or leave max_steps at 0"
                                   : std::string("the mesh may be thinner than the radius allows, open or "
                                                 "self-intersecting (see `pfill info`)")));
  if (result.lost_outside > 2 * std::max<size_t>(result.expected, 1))
    result.warnings.push_back(std::to_string(result.lost_outside) +
                              " particles left through the surface and were removed, more than twice the "
                              "count: the surface has holes or intersects itself (see `pfill info`)");
  return result;
}

}  // namespace pfill
