// The fill, read top-down as the algorithm of DESIGN.md:
//
//   prepare: mesh -> boundary -> signed distance field -> birth sites -> engine
//   pass 1:  while not overfull: births at the sites; update (by default
//            in waves over sites spread through the inside: see birth_wave)
//   pass 2:  MaxParts = count - 1; top up to MaxParts (refill what was lost)
//   settle:  update until at rest
//   finish:  relax overlaps away by moving spheres (a damped repulsive
//            minimisation at a contact distance inflated by the bound);
//            delete only where it stalls over the bound; fill holes
//   verify:  exact containment repair and metrics
//
// The host never reads positions per step: it runs `sync_every` steps (a
// wave's `birth_every` with waves), then reads the step history (kinetic
// energy, colliding pairs, ...) and a snapshot of the positions that the
// birth-room test uses.
#include "pfill/fill.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <random>

#include "pfill/boundary.hpp"
#include "pfill/device/device.hpp"
#include "pfill/engine/engine.hpp"
#include "pfill/error.hpp"
#include "pfill/mesh_diagnostics.hpp"
#include "pfill/peak_memory.hpp"
#include "pfill/sdf.hpp"
#include "fill/finish.hpp"
#include "fill/particle_set_of.hpp"
#include "fill/time_left.hpp"

namespace pfill {
namespace {

constexpr double kPi = 3.14159265358979323846;
// The packing a fill reaches at a bound on the overlaps (a fraction of r),
// so that -n N gives about N. Looser bounds pack denser; spheres pack looser
// against the wall, whose share of the inside is about `wall` = S r / V
// (surface S, volume V). Fitted to spot at the 0.1% bound (0.551 at -n 500,
// 0.597 at 4,000), at 5% (0.636 at 4,000), and a sphere (0.566 at 250,
// 0.604 at 2,000).
double expected_packing(double max_overlap, double wall) {
  // (a few spheres in a thin part: the fit says nothing there; 0.3 keeps the radius sensible)
  return std::max(0.3, 0.643 + 0.79 * std::min(max_overlap, 0.05) - 0.19 * wall);
}

constexpr size_t kMaxParticles = 100'000'000;
// Steps between waves: slower waves compress more gently and pack denser
// (spot, -n 16,000: every 24 steps 0.642, every 48 0.646), while pass 1
// stays about 20,000 steps at any count.
constexpr int kWaveEvery = 48;
// The automatic schedule's switch to waves (FillOptions::sites = -1): below
// this count the report's two sites pack denser (spot -n 1000: 0.574
// against 0.570; a self-intersecting pair of cubes at 300: 0.56 against
// 0.42) and take no longer; from it on, waves are faster (spot -n 4000:
// 8.2 s against 12.9 s; the bunny 11 s against 19 s).
constexpr size_t kWavesFrom = 2000;

// The radius of a fill of `volume` and surface `area`: -r, or the one that
// gives about -n particles. Particles keep the rest distance apart, so with
// a count the spacing, not the sphere, is what must fit (the report's Fig. 4).
double particle_radius(const FillOptions& o, double volume, double area) {
  return o.radius > 0 ? o.radius : fill_radius_for_count(volume, area, o.count, o.max_overlap) / o.rest_distance;
}

// About how many particles fill `volume` when they keep `half_rest` (half
// the rest distance) from each other, overlapping by at most `max_overlap`.
double expected_count(double volume, double area, double half_rest, double max_overlap) {
  return expected_packing(max_overlap, area * half_rest / volume) * volume /
         (4.0 / 3.0 * kPi * half_rest * half_rest * half_rest);
}

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::string fmt(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}


class FillRun {
 public:
  /// `diagnostics`: diagnose(mesh), which the caller has already needed.
  FillRun(const Mesh& mesh, const MeshDiagnostics& diagnostics, const FillOptions& options)
      : mesh_(mesh), diagnostics_(diagnostics), o_(options), rng_(options.seed) {}

  FillResult run() {
    prepare();
    pass1();
    pass2();
    settle();
    finish();
    verify();
    result_.seconds = seconds_since(start_);
    result_.steps = fill_steps_ + relax_steps_;
    result_.peak_memory = peak_resident_bytes();
    return std::move(result_);
  }

 private:
  // ---- prepare: geometry, radius, field, sites, engine ----
  void prepare() {
    check_options();
    const MeshDiagnostics& d = diagnostics_;
    if (d.boundary_edges > 0)
      result_.warnings.push_back("the mesh is open (" + std::to_string(d.boundary_loops) +
                                 " holes): inside is decided by a majority of rays; particles near the holes may "
                                 "be removed by the final check");
    if (d.inside_out()) {
      flip_orientation(mesh_);
      result_.warnings.push_back("the mesh was inside-out (negative volume): its orientation was reversed");
    }
    volume_ = d.volume();
    if (!(volume_ > 0)) throw Error(mesh_.source + ": the mesh encloses no volume; pfill needs a closed solid");

    radius_ = particle_radius(o_, volume_, d.surface_area);
    if (!(radius_ > 0)) throw Error("give a particle radius (-r) or a count (-n)");
    const double expected = expected_count(volume_, d.surface_area, radius_ * o_.rest_distance, o_.max_overlap);
    if (expected > kMaxParticles)
      throw Error("a radius of " + fmt(radius_) + " would give about " + fmt(expected) +
                  " particles, more than pfill handles (" + fmt(kMaxParticles) +
                  "); choose a larger radius or a smaller count");
    result_.radius = radius_;
    result_.expected = static_cast<size_t>(std::llround(expected));

    report("field");
    boundary_ = std::make_unique<Boundary>(mesh_);
    SdfOptions so(o_.field_spacing * radius_);
    const Box3 box = mesh_.bounds();
    const Vec3 size = box.size();
    const double margin = 3 * so.spacing + 2 * radius_;
    auto samples = [&](double h) {
      return (size.x + 2 * margin) / h * (size.y + 2 * margin) / h * (size.z + 2 * margin) / h;
    };
    if (samples(so.spacing) > static_cast<double>(o_.max_field_samples)) {
      so.spacing *= std::cbrt(samples(so.spacing) / static_cast<double>(o_.max_field_samples)) * 1.01;
      result_.warnings.push_back("the distance field was coarsened to a spacing of " + fmt(so.spacing / radius_) +
                                 " r to stay within " + fmt(static_cast<double>(o_.max_field_samples)) +
                                 " samples; the final exact check corrects what it misses");
    }
    so.margin = 2 * radius_ + 3 * so.spacing;
    so.band = std::max(3 * radius_, 4 * so.spacing);
    SdfStats stats;
    field_ = build_signed_distance_field(*boundary_, so, &stats);
    throw_if_cancelled();  // the field can take seconds; the device's program build too
    result_.field_seconds = stats.seconds;
    result_.field_bytes = stats.bytes;
    result_.field_spacing = so.spacing;

    waves_ = o_.sites == 0 || (o_.sites < 0 && result_.expected >= kWavesFrom);
    birth_every_ = o_.birth_every > 0 ? o_.birth_every : (waves_ ? kWaveEvery : 3);
    birth_clearance_ = o_.birth_clearance > 0 ? o_.birth_clearance : (waves_ ? 0.55 : 0.5);
    if (waves_) sites_ = spread_birth_sites(field_, o_.site_spacing * rest_distance(), o_.site_min_depth * radius_);
    if (sites_.empty())  // the report's sites; for waves, the one deepest point of a thin object
      sites_ = choose_birth_sites(field_, o_.sites < 0 ? 2 : std::max(1, o_.sites), radius_, o_.site_depth_share);
    if (sites_.empty()) {
      double deepest = 0;
      for (float v : field_.values) deepest = std::max(deepest, -static_cast<double>(v));
      throw Error("no particle of radius " + fmt(radius_) + " fits: the deepest point is " + fmt(deepest) +
                  " from the surface; choose a smaller radius or a larger count");
    }
    if (o_.birth_point) {
      const Vec3 p = *o_.birth_point;
      if (!boundary_->inside(p))
        throw Error("--birth " + fmt(p.x) + "," + fmt(p.y) + "," + fmt(p.z) +
                    " is outside the mesh; give a point inside it or leave --birth out");
      const double depth = -boundary_->signed_distance(p);
      if (depth < radius_)
        throw Error("--birth point is only " + fmt(depth) + " from the surface, less than the radius " +
                    fmt(radius_) + "; move it deeper inside");
      sites_[0] = {p, depth};
    }
    result_.sites = sites_;

    if (!o_.engine) device_ = std::make_unique<Device>(o_.device);
    result_.device = device_ ? device_->info().name : std::string("none (FillOptions::engine)");
    const size_t bytes_needed = static_cast<size_t>(expected * 2 + 1024) * 96 + stats.bytes;
    if (device_ && device_->info().global_memory > 0 && bytes_needed > device_->info().global_memory)
      throw Error("about " + fmt(expected) + " particles need ~" + fmt(bytes_needed / 1048576.0) + " MiB but " +
                  device_->info().name + " has " + fmt(device_->info().global_memory / 1048576.0) +
                  " MiB; choose a larger radius or another device (--device)");
    params_.radius = radius_;
    params_.max_radius = radius_ * (1 + 1e-6);  // radii come back from the device as floats
    params_.rest_distance = o_.rest_distance * 2 * radius_;
    params_.eps = o_.epsilon;
    params_.exponent_a = o_.exponent_a;
    params_.exponent_b = o_.exponent_b;
    params_.cutoff_sigma = o_.cutoff;
    params_.restitution = o_.restitution;
    params_.wall_restitution = o_.wall_restitution;
    params_.damping = o_.damping;
    params_.dt = o_.time_step * derive_constants(params_).tau;
    params_.max_step_fraction = o_.max_step_fraction;
    params_.skin_sigma = o_.skin;
    engine_ = o_.engine ? o_.engine(params_) : std::make_unique<Engine>(*device_, params_);
    if (o_.log) o_.log(engine_->describe());
    engine_->share_field(field_);  // on PoCL read in place (field_ outlives engine_)
    top_speed_ = engine_->constants().max_speed;
  }

  void check_options() const {
    auto need = [](bool ok, const std::string& what) {
      if (!ok) throw Error(what);
    };
    need(o_.radius >= 0 && std::isfinite(o_.radius), "the radius must be a positive number");
    need(o_.radius > 0 || o_.count > 0, "give a particle radius (-r) or a count (-n)");
    need(o_.count <= kMaxParticles, "a count of " + std::to_string(o_.count) + " is more than pfill handles (" +
                                        fmt(kMaxParticles) + "); ask for fewer particles");
    need(o_.rest_distance >= 1, "--rest-distance must be >= 1 (a multiple of the contact distance 2r)");
    need(o_.sites >= -1 && o_.sites <= 64, "--sites must be -1..64 (-1: automatic; 0: births in waves over sites spread inside)");
    need(o_.birth_every >= 0, "--birth-every must be >= 1 (or 0: automatic)");
    need(o_.birth_stop_share == -1 || (o_.birth_stop_share >= 0 && o_.birth_stop_share < 1),
         "the birth stop share must be in [0, 1), or -1 for automatic");
    need(o_.site_spacing >= 0.5, "--site-spacing must be >= 0.5 rest distances");
    need(o_.site_min_depth >= 1, "--site-min-depth must be >= 1 radius");
    need(o_.birth_speed_min >= 0 && o_.birth_speed_max >= o_.birth_speed_min && o_.birth_speed_max <= 1,
         "birth speeds must satisfy 0 <= min <= max <= 1 (fractions of the top speed)");
    need(o_.max_overlap >= 0 && o_.max_overlap < 1, "--max-overlap must be in [0, 1) (a fraction of r)");
    need(o_.field_spacing > 0 && o_.field_spacing <= 2, "the field spacing must be in (0, 2] radii");
    need(o_.time_step > 0 && o_.time_step <= 0.05, "--time-step must be in (0, 0.05] tau");
    need(o_.sync_every >= 1 && o_.sync_every <= 1000, "sync_every must be 1..1000");
    need(o_.sort_every >= 0, "sort_every must be >= 0 (0: never)");
    // Bounds that keep every pass finite: a site that always has room, a
    // patience of nothing, a vanishing step or speed would make a fill
    // endless or empty.
    need(o_.birth_clearance == 0 || (o_.birth_clearance >= 0.25 && o_.birth_clearance <= 4),
         "--birth-clearance must be 0 (automatic) or in [0.25, 4] rest distances; below 0.25 a site never "
         "fills up and births go on without end");
    need(o_.blocked.patience >= std::max(100, 10 * o_.birth_every) && o_.blocked.patience <= 10'000'000,
         "--patience must be at least 100 steps and 10 birth intervals (--birth-every), at most 10,000,000 "
         "(default 1500)");
    need(o_.birth_every <= 1000, "--birth-every must be 1..1000");
    need(o_.site_depth_share >= 0 && o_.site_depth_share <= 1,
         "--site-depth must be in [0, 1] (a share of the deepest point's depth)");
    need(o_.void_rounds >= 0 && o_.void_rounds <= 100, "--void-rounds must be 0..100");
    need(o_.void_clearance > 0 && o_.void_clearance <= 4, "--void-clearance must be in (0, 4] rest distances");
    need(o_.time_step >= 1e-4, "--time-step must be at least 0.0001 tau (smaller steps never finish)");
    need(o_.max_step_fraction >= 1e-3 && o_.max_step_fraction <= 1, "--max-step must be in [0.001, 1] sigma");
    need(o_.rest_distance <= 10, "--rest-distance must be 1..10");
    need(std::isfinite(o_.epsilon) && o_.epsilon > 0, "--epsilon must be a positive number");
    need(o_.cutoff == 0 || (o_.cutoff > 1 && o_.cutoff <= 5), "--cutoff must be 0 (purely repulsive) or in (1, 5] sigma");
    need(o_.restitution >= 0 && o_.restitution <= 1 && o_.wall_restitution >= 0 && o_.wall_restitution <= 1,
         "--restitution and --wall-restitution must be in [0, 1]");
    need(std::isfinite(o_.damping) && o_.damping >= 0, "--damping must be >= 0");
    need(o_.skin >= 0 && o_.skin <= 5, "--skin must be in [0, 5] sigma (0: automatic)");
    need(o_.top_up_patience >= 1 && o_.rest_steps >= 1 && o_.rest_speed > 0,
         "the settling settings must be positive");
  }

  // ---- pass 1: births until the object is overfull ----
  void pass1() {
    const auto t = Clock::now();
    const uint64_t first = engine_->steps_done();
    const uint64_t budget = o_.max_steps ? o_.max_steps : 100 * result_.expected + 20000;
    KineticEnergyTest ke(o_.ke);
    CollisionCountTest collisions(o_.collisions);
    // Over many sites a few keep finding room now and then long after the
    // object is full: waves end when births fall to a small share.
    BlockedSitesSettings bs = o_.blocked;
    bs.share = !waves_ ? 0 : o_.birth_stop_share >= 0 ? o_.birth_stop_share : o_.max_overlap < 0.01 ? 0.03 : 0.003;
    BlockedSitesTest blocked(bs);
    time_left_ = TimeLeft({waves_, static_cast<double>(result_.expected), static_cast<double>(bs.patience), bs.share,
                           static_cast<double>(o_.settle_budget)});
    time_left_.pass1_started(first);
    phase_ = "pass 1";
    bool overfull = false;
    while (!overfull) {
      const bool hold = ke.waiting() || collisions.waiting();
      const std::vector<int> born = run_batch(!hold);
      for (size_t k = 0; k < history_.size() && !overfull; ++k) {
        const StepRecord& r = history_[k];
        const int births = k < born.size() ? born[k] : 0;
        const bool b = births > 0;
        StopVerdict v = StopVerdict::Continue;
        if (o_.stop == StopCriterion::KineticEnergy) v = ke.observe(r, b);
        if (o_.stop == StopCriterion::Collisions) v = collisions.observe(r, b);
        if (v == StopVerdict::RemoveNewest) {
          remove_newest();
        } else if (v == StopVerdict::Overfull) {
          overfull = true;
          result_.stop_signal = to_string(o_.stop);
          result_.stop_reason =
              o_.stop == StopCriterion::KineticEnergy
                  ? "the kinetic energy rose over " + std::to_string(o_.ke.rising_steps) + " steps " +
                        std::to_string(ke.events()) + " times"
                  : "the colliding-pair count stayed unchanged and could not be lowered after " +
                        std::to_string(o_.collisions.max_tries) + " removals";
        }
        // The blocked-sites test always runs: it ends the pass when the
        // report's tests never fire (a prototype found they rarely do).
        if (!overfull && blocked.observe(births, engine_->size()) == StopVerdict::Overfull) {
          overfull = true;
          result_.stop_signal = "blocked";
          result_.stop_reason =
              (blocked.steps_without_birth() >= bs.patience
                   ? "no birth site had room for " + std::to_string(bs.patience) + " steps"
                   : "the " + std::to_string(sites_.size()) + " sites had room for at most " + fmt(bs.share * 100) +
                         "% of the particles in the last " + std::to_string(bs.patience) + " steps") +
                                (o_.stop != StopCriterion::Blocked
                                     ? std::string(" (the ") + to_string(o_.stop) + " test did not fire first)"
                                     : "");
        }
      }
      result_.ke_events = ke.events();
      result_.collision_events = collisions.tries();
      if (!overfull && engine_->steps_done() - first >= budget) {
        overfull = true;
        result_.stop_signal = "budget";
        result_.stop_reason = "the step budget of pass 1 (" + std::to_string(budget) + " steps) ran out";
      }
    }
    result_.passes.push_back({"pass 1", engine_->steps_done() - first, seconds_since(t)});
    time_left_.pass1_ended();
  }

  // ---- pass 2: MaxParts = count - 1; top up to it ----
  void pass2() {
    const auto t = Clock::now();
    const uint64_t first = engine_->steps_done();
    phase_ = "pass 2";
    result_.max_parts = engine_->size() > 0 ? engine_->size() - 1 : 0;
    if (engine_->size() > result_.max_parts && engine_->size() > 1) remove_newest();
    int idle = 0;
    while (engine_->size() < result_.max_parts && idle < o_.top_up_patience) {
      const std::vector<int> born = run_batch(true);
      const bool any = std::any_of(born.begin(), born.end(), [](int b) { return b > 0; });
      idle = any ? 0 : idle + static_cast<int>(born.size());
    }
    result_.passes.push_back({"pass 2", engine_->steps_done() - first, seconds_since(t)});
  }

  // ---- settle: run until at rest ----
  void settle() {
    const auto t = Clock::now();
    const uint64_t first = engine_->steps_done();
    phase_ = "settle";
    time_left_.settle_started(first);
    int calm = 0;
    result_.settle_reason = "the step budget (" + std::to_string(o_.settle_budget) + " steps) ran out";
    while (engine_->steps_done() - first < o_.settle_budget) {
      run_batch(false);
      for (const StepRecord& r : history_) calm = r.max_speed < o_.rest_speed * top_speed_ ? calm + 1 : 0;
      if (calm >= o_.rest_steps) {
        result_.settle_reason = "at rest: every speed below " + fmt(o_.rest_speed) + " of the top speed for " +
                                std::to_string(o_.rest_steps) + " steps";
        break;
      }
    }
    result_.passes.push_back({"settle", engine_->steps_done() - first, seconds_since(t)});
  }

  // ---- finish: overlaps resolved by moving spheres; holes filled (finish.cpp) ----
  void finish() {
    const auto t = Clock::now();
    phase_ = "finish";
    time_left_.finish_started(seconds_since(start_));
    fill_steps_ = engine_->steps_done();
    std::vector<Particle> ps = engine_->read_particles();
    engine_.reset();  // the finish holds the particles from here on
    if (!device_ && !o_.finish_on_engine) {  // FillOptions::engine: no OpenCL engine for the finish
      particles_ = to_particle_set(ps);
      result_.warnings.push_back("the finish was left out: it needs the OpenCL engine (FillOptions::engine was given)");
      return;
    }
    report_particles(ps.size(), 0, 0);  // the phase starts (progress lines, time left)
    const FinishSettings s = finish_settings();
    FinishStats stats;
    auto progress = [&](size_t n, uint32_t pairs) {
      relax_steps_ = stats.steps;  // the finish's steps so far, for the progress line
      report_particles(n, 0, pairs);
    };
    particles_ = device_ ? finish_packing(*device_, params_, field_, std::move(ps), s, stats, progress)
                         : finish_packing(o_.engine, params_, field_, std::move(ps), s, stats, progress);
    relax_steps_ = stats.steps;
    field_ = ScalarGrid();  // (memory: up to 256 MiB) nothing after the finish samples the field
    result_.relief_removed = stats.removed;
    result_.relief_forced = stats.forced;
    result_.relief_rounds = stats.rounds;
    result_.voids_filled = stats.inserted;
    next_id_ = stats.next_id;
    result_.passes.push_back({"finish", stats.steps, seconds_since(t)});
  }

  FinishSettings finish_settings() const {
    FinishSettings s;
    s.radius = radius_;
    s.max_overlap = o_.max_overlap;
    s.hole_rounds = o_.void_rounds;
    s.hole_clearance = o_.void_clearance * 2 * o_.rest_distance;
    s.fit_clearance = 2 * o_.rest_distance;
    s.first_id = next_id_;
    s.cancelled = o_.cancelled;
    return s;
  }

  // ---- verify: exact containment, then the metrics ----
  void verify() {
    phase_ = "verify";
    report_particles(particles_.size(), 0, 0);
    result_.containment =
        repair_containment(*boundary_, particles_, o_.containment_tolerance, o_.max_overlap);
    // Holes the field hid (near the wall) or the repair opened take a sphere
    // where, by exact distances, one fits inside without overlap.
    // (A hole "fits" a sphere at the rest distance: 2r, or more for sparse fills.)
    Hole h = largest_hole(*boundary_, particles_, radius_);
    // The exact inside test (a majority of rays on open meshes) has the last word.
    for (int k = 0; k < 32 && o_.void_rounds > 0 && h.gap_over_r >= 2 * o_.rest_distance - 1 &&
                    boundary_->signed_distance(h.centre) <= -radius_;
         ++k) {
      particles_.positions.push_back(h.centre);
      particles_.radii.push_back(radius_);
      particles_.ids.push_back(next_id_++);
      if (particles_.has_velocities()) particles_.velocities.push_back({});
      ++result_.voids_filled;
      h = largest_hole(*boundary_, particles_, radius_);
    }
    MetricsOptions mo;
    mo.containment_tolerance = o_.containment_tolerance;
    mo.holes = false;  // measured just now
    result_.metrics = measure_packing(*boundary_, volume_, particles_, mo);
    result_.metrics.largest_hole = h.gap_over_r;
    ColourOptions colour = o_.colour ? *o_.colour : ColourOptions{default_colour_mode(mesh_), {}};
    const std::string note = colour_particles(*boundary_, particles_, colour);
    if (!note.empty()) result_.warnings.push_back(note);
    result_.particles = std::move(particles_);
  }

  // ---- the machinery shared by the passes ----

  /// Runs `sync_every` steps (with birth attempts when `births`), then reads
  /// the history (and, while births may follow or a frame is due, a snapshot of the
  /// positions), removes flagged particles, reports progress.
  /// Returns, per step of the batch, how many particles were born before it.
  std::vector<int> run_batch(bool births) {
    throw_if_cancelled();
    // Waves: one wave a batch, right after the snapshot it tests room on.
    const int steps = waves_ ? birth_every_ : o_.sync_every;
    std::vector<int> born(static_cast<size_t>(steps), 0);
    if (o_.sort_every > 0 && engine_->steps_done() >= next_sort_) renumber_along_cells();
    for (int s = 0; s < steps; ++s) {
      const bool due = waves_ ? s == 0 : engine_->steps_done() % static_cast<uint64_t>(birth_every_) == 0;
      if (births && due && (phase_ != "pass 2" || engine_->size() < result_.max_parts))
        born[s] = waves_ ? birth_wave() : birth_at_sites();
      engine_->run_steps(1);
    }
    history_ = engine_->read_history();
    uint32_t flagged = 0;
    for (const StepRecord& r : history_) flagged = std::max(flagged, r.flagged);
    if (flagged > 0) {
      const std::vector<size_t> out = flagged_of(*engine_);
      result_.lost_outside += out.size();
      follow_newest_through_removals(out);
      engine_->remove_particles(out);
    }
    // Positions come back only for what needs them: the birth-room test and frames.
    const bool frame_due = o_.on_frame && o_.frame_every && engine_->steps_done() / o_.frame_every != last_frame_;
    const bool births_ahead = phase_ == "pass 1" || phase_ == "pass 2";  // a hold may end next batch
    if (births_ahead || frame_due) {
      const std::vector<Particle> ps = engine_->read_particles();
      snapshot_.clear();
      for (const Particle& p : ps) snapshot_.push_back(p.position);
      newborns_.clear();
      if (frame_due) {
        last_frame_ = engine_->steps_done() / o_.frame_every;
        o_.on_frame(engine_->steps_done(), to_particle_set(ps));
      }
    }
    if (!history_.empty())
      report_particles(engine_->size(), history_.back().kinetic_energy, history_.back().colliding_pairs);
    return born;
  }

  /// The caller's cancel hook (FillOptions::cancelled), polled at each sync.
  void throw_if_cancelled() const {
    if (o_.cancelled && o_.cancelled()) throw Cancelled();
  }

  /// Centre distance at the potential's minimum: the spacing the user asked
  /// for (2r, or more for sparser fills), which the room tests scale with.
  double rest_distance() const { return o_.rest_distance * 2 * radius_; }

  /// One newborn at each site with room; returns how many were born.
  int birth_at_sites() {
    int born = 0;
    const double clearance = birth_clearance_ * rest_distance();
    for (const BirthSite& site : sites_) {
      if (phase_ == "pass 2" && engine_->size() >= result_.max_parts) break;
      if (!site_has_room(snapshot_, site.position, clearance) || !newborns_clear(site.position, clearance)) continue;
      const Particle p = newborn_at(site.position);
      newest_ = engine_->add_particle(p);
      newborns_.push_back({p.position, p.velocity, engine_->steps_done()});
      ++born;
    }
    return born;
  }

  /// A wave: one newborn at every site with room in the snapshot just
  /// read (a grid of it answers each site in O(1)), added in one upload.
  /// Sites lie several rest distances apart, so newborns of one wave
  /// never crowd each other. Returns how many were born.
  int birth_wave() {
    const RoomGrid room(snapshot_, birth_clearance_ * rest_distance());
    std::vector<Particle> newborns;
    for (const BirthSite& site : sites_) {
      if (phase_ == "pass 2" && engine_->size() + newborns.size() >= result_.max_parts) break;
      if (room.has_room(site.position)) newborns.push_back(newborn_at(site.position));
    }
    if (!newborns.empty()) newest_ = engine_->add_particles(newborns) + newborns.size() - 1;
    return static_cast<int>(newborns.size());
  }

  Particle newborn_at(const Vec3& position) {
    Particle p;
    p.position = position;
    p.radius = radius_;
    p.id = next_id_++;
    p.velocity = random_direction() *
                 (top_speed_ * (o_.birth_speed_min + (o_.birth_speed_max - o_.birth_speed_min) * speed_(rng_)));
    return p;
  }

  /// Newborns since the last snapshot fly straight at their birth speed
  /// (they are the fastest particles there): predicted, they need no read-back.
  bool newborns_clear(const Vec3& site, double clearance) const {
    const double dt = engine_->constants().dt;
    for (const Newborn& b : newborns_) {
      const Vec3 now = b.position + b.velocity * (dt * static_cast<double>(engine_->steps_done() - b.step));
      if (length(now - site) < clearance) return false;
    }
    return true;
  }

  Vec3 random_direction() {
    std::normal_distribution<double> g(0, 1);
    for (;;) {
      const Vec3 v{g(rng_), g(rng_), g(rng_)};
      const double l = length(v);
      if (l > 1e-9) return v / l;
    }
  }

  /// Removes the newest particle (the report's "remove the last born");
  /// when it is gone already (removed outside), the last index instead.
  void remove_newest() {
    if (engine_->size() == 0) return;
    const size_t idx = newest_ < engine_->size() ? newest_ : engine_->size() - 1;
    follow_newest_through_removals({idx});
    engine_->remove_particles({idx});
  }

  /// Keeps newest_ pointing at the newest particle through removals.
  void follow_newest_through_removals(const std::vector<size_t>& removed) {
    newest_ = Engine::index_after_removal(newest_, removed, engine_->size());
  }

  /// Renumbers the particles along the cells (Engine::sort_by_cells): the
  /// births scatter them through memory, and near in space near in memory
  /// makes every kernel of a step read from cache (a fill of spot ran
  /// about 20% more steps a second with this every 1,024 steps; every 256,
  /// pass 1 of spot -n 16000 took another 15% less kernel time a step).
  void renumber_along_cells() {
    const std::vector<size_t> order = engine_->sort_by_cells();
    if (newest_ != Engine::kGone)
      newest_ = static_cast<size_t>(std::find(order.begin(), order.end(), newest_) - order.begin());
    next_sort_ = engine_->steps_done() + static_cast<uint64_t>(o_.sort_every);
  }

  static std::vector<size_t> flagged_of(ParticleEngine& e) {
    std::vector<size_t> out = e.flagged_particles();
    e.clear_flags();
    return out;
  }

  void report(const std::string& phase) {
    phase_ = phase;
    report_particles(0, 0, 0);
  }

  void report_particles(size_t n, double ke, uint32_t pairs) {
    if (!o_.progress) return;
    FillProgress p;
    p.phase = phase_;
    p.step = (engine_ ? engine_->steps_done() : fill_steps_) + relax_steps_;
    p.particles = n;
    p.target = result_.expected;
    p.kinetic_energy = ke;
    p.colliding_pairs = pairs;
    p.elapsed = seconds_since(start_);
    const double dt = seconds_since(last_report_);
    if (dt > 0 && p.step >= last_step_) p.steps_per_second = (p.step - last_step_) / dt;
    last_report_ = Clock::now();
    last_step_ = p.step;
    p.remaining = time_left_.estimate(phase_, p.elapsed, n, p.step, relax_steps_);
    p.peak_memory = peak_resident_bytes();
    o_.progress(p);
  }

  Mesh mesh_;
  MeshDiagnostics diagnostics_;
  FillOptions o_;
  std::mt19937_64 rng_;
  std::uniform_real_distribution<double> speed_{0, 1};
  Clock::time_point start_ = Clock::now();
  Clock::time_point last_report_ = Clock::now();
  uint64_t last_step_ = 0;
  TimeLeft time_left_{TimeLeftSchedule{}};  ///< for the progress line's seconds left
  uint64_t last_frame_ = 0;
  double volume_ = 0;
  double radius_ = 0;
  double top_speed_ = 0;
  std::unique_ptr<Boundary> boundary_;
  ScalarGrid field_;
  std::vector<BirthSite> sites_;
  bool waves_ = false;   ///< births in waves over spread sites (FillOptions::sites == 0)
  int birth_every_ = 3;  ///< steps between births at a site
  double birth_clearance_ = 0.5;  ///< room test radius, in rest distances
  std::unique_ptr<Device> device_;
  EngineParams params_;
  std::unique_ptr<ParticleEngine> engine_;
  std::vector<StepRecord> history_;
  std::vector<Vec3> snapshot_;
  size_t newest_ = Engine::kGone;  // index of the last particle born (kGone: removed)
  uint64_t next_sort_ = 0;     // step of the next renumbering along the cells
  uint64_t next_id_ = 1;       // ids in birth order; the engines carry them (Particle::id)
  struct Newborn {
    Vec3 position, velocity;
    uint64_t step;
  };
  std::vector<Newborn> newborns_;  ///< born since the last snapshot
  ParticleSet particles_;
  uint64_t relax_steps_ = 0;
  uint64_t fill_steps_ = 0;  ///< engine steps of passes 1-3, kept once the engine is gone
  std::string phase_;
  FillResult result_;
};

}  // namespace

double fill_radius_for_count(double volume, double area, size_t count, double max_overlap) {
  if (!(volume > 0) || count == 0) return 0;
  // The packing depends on the radius a little (the wall's share): a few rounds settle it.
  const double n = static_cast<double>(count);
  double r = std::cbrt(3.0 * 0.6 * volume / (4.0 * kPi * n));
  for (int k = 0; k < 6; ++k)
    r = std::cbrt(3.0 * expected_packing(max_overlap, std::max(area, 0.0) * r / volume) * volume / (4.0 * kPi * n));
  return r;
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
  return "no particle of radius " + fmt(radius) + " fits: the deepest point is about " + fmt(deepest) +
         " from the surface; " +
         (o.radius > 0 ? "choose a radius below " + fmt(deepest) : std::string("ask for more particles (-n)"));
}

// A mesh whose box the distance field cannot cover at a spacing near the
// radius (a stray vertex far from the rest makes one) would build a field
// of billions of samples or fill nothing: say which vertex lies farthest
// from the median of all, and stop.
void refuse_stray_vertices(const Mesh& mesh, double volume, double area, const FillOptions& o) {
  const double radius = particle_radius(o, volume, area);
  if (!(radius > 0) || mesh.positions.empty()) return;
  // Too many particles is the first thing to say (the run's check says it).
  const double half_rest = radius * o.rest_distance;
  if (o.count > kMaxParticles || expected_count(volume, area, half_rest, o.max_overlap) > kMaxParticles)
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
  throw Error((mesh.source.empty() ? std::string("the mesh") : mesh.source) + ": its box (" + fmt(size.x) + " x " +
              fmt(size.y) + " x " + fmt(size.z) + ") is too large for particles of radius " + fmt(radius) +
              " (a volume of " + fmt(volume) + "): is the vertex at (" + fmt(p.x) + ", " + fmt(p.y) + ", " + fmt(p.z) +
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
  FillOptions o = options;
  if (o.birth_point) o.birth_point = *o.birth_point - centre;
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
        ": filled as the union of what it encloses (inside = a non-zero winding number); the volume " + fmt(d.volume()) +
        " is the union's, estimated by rays" +
        (d.components > 1 ? "" : ", and its inner surfaces act as walls; repair the mesh for a clean fill"));

  // A fill that ends empty or far short of its estimate is not a result.
  if (result.particles.size() == 0)
    throw Error(name + ": the fill ended with no particles (" + std::to_string(result.lost_outside) +
                " left through the surface); check the mesh with `pfill info` (open, self-intersecting or "
                "too thin for the radius?)");
  if (result.expected > 0 && result.particles.size() * 4 < result.expected)
    result.warnings.push_back("only " + std::to_string(result.particles.size()) + " particles of the ~" +
                              std::to_string(result.expected) + " expected: the mesh may be thinner than the "
                              "radius allows, open or self-intersecting (see `pfill info`)");
  if (result.lost_outside > 2 * std::max<size_t>(result.expected, 1))
    result.warnings.push_back(std::to_string(result.lost_outside) +
                              " particles left through the surface and were removed, more than twice the "
                              "count: the surface has holes or intersects itself (see `pfill info`)");
  return result;
}

}  // namespace pfill
