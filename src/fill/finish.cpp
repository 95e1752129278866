// The finish (see finish.hpp). Overlaps are resolved by moving spheres: a
// purely repulsive relaxation, by FIRE (EngineParams::fire: inertia while
// the energy falls, every velocity dropped when it rises) or, on engines
// without it, lightly damped dynamics, whose rest distance is set by the
// bound (finish_inflation), with the wall keeping every centre inside. The
// engine's spheres are smaller than r by half the bound, so the colliding
// pairs it counts each step are the pairs over the bound: a relaxation ends
// when that count is 0 or stops falling, with no positions read; one that
// runs out of steps while the count still falls runs on. Only
// when it stalls above 0 is the packing too full there: then the
// most compressed spheres go, about half as many as the overlaps imply
// (FinishSettings::removal_share, fire_removal_share), and one in each of the most pressed tenth of the jams,
// never two touching ones in a round, and the relaxation runs again.
// The last few jams of a large packing relax on their own: only the
// spheres near them move, on an engine of their own (a relaxation of all N
// for a few hundred pairs cost spot at 1e6 a quarter of its fill).
// Holes the relaxed packing leaves get a sphere, relaxed in, while a
// round finds enough; then every hole a sphere fits without overlap gets
// one as it is. If the rounds run out, one sphere of each pair still over
// the bound goes, so the bound always holds.
//
// The device runs the relaxation; the host reads the step history every
// `chunk_steps` steps (a few scalars) and the positions once a relaxation.
#include "fill/finish.hpp"
#include "fill/near_region.hpp"
#include "fill/particle_set_of.hpp"
#include "fill/size_deficit.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

#include "pfill/error.hpp"
#include "pfill/packing_metrics.hpp"
#include "pfill/sdf.hpp"
#include "pfill/voids.hpp"

namespace pfill {
namespace {

/// A held sphere's mass in a local relaxation: its speed stays 0 to float precision.
constexpr double kHeldMass = 1e30;

/// The engine's particles at their true radii (the engine's are smaller by
/// `shrink`: half the bound of the smallest).
ParticleSet to_set(const std::vector<Particle>& ps, double radius, double shrink, bool unequal) {
  ParticleSet set = to_particle_set(ps);
  if (!unequal) {
    set.radii.assign(ps.size(), radius);  // exact: the engine's floats would round it
  } else {
    for (double& r : set.radii) r += shrink;
  }
  return set;
}

/// Each sphere's overlapping partners, one run each: partners[first[i]] up
/// to partners[first[i + 1]] (a vector a sphere cost ~70 MiB at 1e6).
struct OverlapPartners {
  OverlapPartners(size_t n, const std::vector<Overlap>& overlaps) : first(n + 1, 0), partners(2 * overlaps.size()) {
    for (const Overlap& o : overlaps) ++first[o.i + 1], ++first[o.j + 1];
    for (size_t i = 0; i < n; ++i) first[i + 1] += first[i];
    std::vector<size_t> next(first.begin(), first.end() - 1);
    for (const Overlap& o : overlaps) partners[next[o.i]++] = o.j, partners[next[o.j]++] = o.i;
  }
  std::vector<size_t> first;
  std::vector<uint32_t> partners;
};

class Finisher {
 public:
  Finisher(const std::function<std::unique_ptr<ParticleEngine>(const EngineParams&)>& make, const EngineParams& base,
           const ScalarGrid& field, const FinishSettings& s, FinishStats& stats)
      : s_(s), field_(field), stats_(stats), make_(make) {
    const double inflation = std::isnan(s.inflation) ? finish_inflation(s.max_overlap) : s.inflation;
    // The engine's spheres are smaller by half the bound, so that the
    // colliding pairs it counts every step are those over the bound, and
    // its wall moves in by as much, so that centres stay r inside.
    // Unequal spheres: every engine sphere is smaller by the same length, so
    // that the pairs counted are those over the bound of the smallest
    // radius, at most the bound of the pair's smaller one.
    shrink_ = 0.5 * s.max_overlap * s.radius;
    engine_radius_ = s.radius - shrink_;
    deep_ = s.radius * (1 + s.wall_margin);
    EngineParams p = base;
    p.cutoff_sigma = 0;  // purely repulsive: attraction would pull spheres together
    p.births_at_speed = false;  // a relaxation: the lists stay fresh longer
    p.rest_distance = 2 * s.radius * (1 + inflation);
    p.max_radius = std::max(base.max_radius, s.radius * (1 + 1e-6));
    p.restitution = 0;
    p.wall_restitution = 0;
    p.dt = 0;
    const double tau = derive_constants(p).tau;
    p.dt = s.time_step * tau;
    if (s.fire) {
      // FIRE minimises the potential itself: no dashpots, no damping
      p.restitution = 1;
      p.damping = 0;
      p.dt = s.fire_time_step * tau;
      p.fire.on = true;
      p.fire.dt_max = s.fire_dt_max;
    } else {
      p.damping = -std::log(1 - s.damping) / p.dt;
    }
    p.history_capacity = std::max<size_t>(p.history_capacity, static_cast<size_t>(s.chunk_steps) + 8);
    p.radius = engine_radius_;
    // The wall also keeps `wall_margin` r more: the field, interpolated,
    // misses some of the surface's bends, which the exact check then finds.
    // (The kernels add the offset as they read the field: no shifted copy.)
    p.wall_offset = s.radius * (1 + s.wall_margin) - engine_radius_;
    params_ = p;
    engine_ = make(p);
    engine_->share_field(field);  // field_ outlives the engine
  }

  ParticleSet run(std::vector<Particle> ps) {
    if (s_.sizes) {
      sizes_.emplace(*s_.sizes);
      sizes_->set_caps(s_.size_caps);
    }
    upload(std::move(ps));
    int holes_done = 0;
    bool compressing = s_.compress_clearance > 0;
    size_t last_inserted = 0, deleted_since_insert = 0;
    ParticleSet now;
    for (int round = 0;; ++round) {
      const bool stalled = relax();
      now = ParticleSet();  // (memory: the last round's set goes before this one's is read)
      now = current();
      const std::vector<Overlap> overlaps = find_overlaps(now, 0.0);
      size_t over = 0;
      hot_.clear();
      for (const Overlap& o : overlaps)
        if (o.fraction > s_.max_overlap) {
          ++over;
          hot_.push_back(0.5 * (now.positions[o.i] + now.positions[o.j]));
        }
      if (over > 0) {
        if (round + 1 >= s_.max_rounds) {
          remove_one_of_each(now, overlaps);
          break;
        }
        // Still falling when the steps ran out: relax on, delete nothing
        // (deleting then cost the bunny at r 0.012253, seed 1, 2% of its
        // packing); but a few pairs left that fall slowly go at once.
        if (!stalled && static_cast<double>(over) > s_.run_on_share * static_cast<double>(now.size())) continue;
        const size_t removed_before = stats_.removed;
        remove_most_compressed(now, overlaps);
        // Compressing ends where it deletes half of what it inserts: the
        // packing is then as full as the bound allows.
        deleted_since_insert += stats_.removed - removed_before;
        if (2 * deleted_since_insert > last_inserted) compressing = false;
        continue;
      }
      if ((!compressing && holes_done >= s_.hole_rounds) || round + 1 >= s_.max_rounds) break;
      if (all_held(now)) break;
      const double clearance = compressing ? s_.compress_clearance : s_.hole_clearance;
      std::vector<double> gaps;
      const std::vector<Vec3> holes =
          find_holes(now, field_, deep_, clearance * s_.radius, now.size(), sizes_ ? s_.radius : 0, &gaps);
      // A round of a few holes does not pay for its relaxation (each takes
      // about 1,500 steps to settle, whatever the number of newcomers): the
      // fit pass below takes those a sphere fits in as they are.
      if (static_cast<double>(holes.size()) < s_.hole_round_share * static_cast<double>(now.size())) {
        if (!compressing) break;
        compressing = false;  // compressed: the ordinary holes next
        continue;
      }
      if (!compressing) ++holes_done;
      hot_.clear();  // newcomers everywhere: the next relaxation is of all
      last_inserted = insert_into_holes(now, holes, gaps, clearance);
      deleted_since_insert = 0;
      // Every class held at its cap: no hole takes a sphere, and another round would only relax.
      if (last_inserted == 0 && sizes_ && sizes_->capped()) break;
    }
    add_fits(now);
    stats_.next_id = next_id_;
    return now;
  }

  void set_progress(const std::function<void(size_t, uint32_t)>& f) { progress_ = f; }

 private:
  /// The spheres onto the engine, at rest, at the engine's radius.
  void upload(std::vector<Particle> ps) {
    for (Particle& p : ps) {
      p.velocity = {};
      p.radius = sizes_ ? p.radius - shrink_ : engine_radius_;
      // One mass for all: the relaxation is a minimiser, and unequal masses
      // left the large spheres slow to give way.
      p.mass = 1;
    }
    engine_->add_particles(ps);
  }

  /// A sphere into each of `holes` (the nearest centre `gaps` away), on
  /// the engine, for the next relaxation to make room for. Returns how many.
  size_t insert_into_holes(const ParticleSet& now, const std::vector<Vec3>& holes, const std::vector<double>& gaps,
                           double clearance) {
    std::vector<Particle> newcomers;
    if (sizes_) sizes_->recount(now.radii);
    for (size_t k = 0; k < holes.size(); ++k) {
      // Unequal spheres: as large as the hole takes at this clearance's
      // overlap (the same share of the radius as for the smallest), of
      // a class still short of its share.
      const double r =
          sizes_ ? hole_radius(holes[k], s_.radius * (gaps[k] - s_.radius) / (clearance * s_.radius - s_.radius))
                 : s_.radius;
      if (r <= 0) continue;
      Particle p;
      p.position = holes[k];
      p.radius = r - shrink_;
      p.mass = 1;
      p.id = next_id_++;
      newcomers.push_back(p);
    }
    engine_->add_particles(newcomers);
    stats_.inserted += newcomers.size();
    return newcomers.size();
  }

  /// After the last relaxation: holes a sphere fits in without overlap (a
  /// deletion after the last insertion may leave one) take one as they
  /// are, into `now`: nothing to relax.
  void add_fits(ParticleSet& now) {
    now = current();
    if (all_held(now)) return;
    std::vector<double> gaps;
    const std::vector<Vec3> fits =
        s_.hole_rounds > 0 ? find_holes(now, field_, deep_, s_.fit_clearance * s_.radius * (1 + 1e-6), now.size(),
                                        sizes_ ? s_.radius : 0, &gaps)
                           : std::vector<Vec3>{};
    if (sizes_) sizes_->recount(now.radii);
    const size_t before = now.size();
    for (size_t k = 0; k < fits.size(); ++k) {
      // Unequal spheres: no larger than the gap to the nearest sphere, nor
      // than to the fits placed before it (each counted as the smallest).
      double r = s_.radius;
      if (sizes_) {
        double room = gaps[k] - s_.radius;
        for (size_t m = before; m < now.size(); ++m)
          room = std::min(room, length(now.positions[m] - fits[k]) - now.radii[m]);
        r = hole_radius(fits[k], room);
        if (r <= 0) continue;
      }
      now.positions.push_back(fits[k]);
      now.radii.push_back(r);
      now.ids.push_back(next_id_++);
      now.velocities.push_back({});
      ++stats_.inserted;
    }
  }

  /// Unequal spheres held to caps (FinishSettings::size_caps), every class
  /// at its cap: no hole may take a sphere, and a search of a loose
  /// packing's many holes would take long for nothing.
  bool all_held(const ParticleSet& now) {
    if (!sizes_ || !sizes_->capped()) return false;
    sizes_->recount(now.radii);
    return sizes_->all_capped();
  }

  /// The spheres now, at their true radii.
  ParticleSet current() const { return to_set(engine_->read_particles(), s_.radius, shrink_, sizes_.has_value()); }

  /// Unequal spheres: the radius a hole at `p` gets, at most `room` (and
  /// deep enough inside by the field): of the class furthest below its
  /// share that fits; 0 when none does.
  double hole_radius(const Vec3& p, double room) {
    return sizes_->take_within(std::min(room, -sample(field_, p) / (1 + s_.wall_margin)), rng_);
  }

  /// A relaxation: of the spheres near the last round's pairs over the
  /// bound (`hot_`) where they are few (relax_near), else of all.
  bool relax() {
    ++stats_.rounds;
    if (!hot_.empty() && engine_->size() >= s_.near_min_spheres)
      if (const std::optional<bool> stalled = relax_near()) return *stalled;
    return relax_on(*engine_, engine_->size());
  }

  /// Relaxes only the spheres within `near_reach` r of a place in `hot_`,
  /// with those up to `near_hold` r further held still (as good as infinite
  /// mass), on an engine of their own; then the main engine takes them
  /// back. One engine at a time: each holds a cell grid over the field's
  /// whole box (~550 MiB at 1e6), and two at once took the peak from 1,645
  /// to 2,166 MiB. Nothing (no relaxation) when the region holds more than
  /// `near_share` of the spheres: a relaxation of all then costs little more.
  std::optional<bool> relax_near() {
    std::vector<Particle> ps = engine_->read_particles();
    const NearRegion region = region_near(ps, hot_, s_.near_reach * s_.radius, s_.near_hold * s_.radius);
    if (static_cast<double>(region.moving.size() + region.held.size()) >
        s_.near_share * static_cast<double>(ps.size()))
      return std::nullopt;
    ++stats_.near_rounds;
    engine_.reset();
    std::unique_ptr<ParticleEngine> local = make_(params_);
    local->share_field(field_);
    local->add_particles(region_particles(ps, region, kHeldMass));
    const bool stalled = relax_on(*local, ps.size());
    const std::vector<Particle> moved = local->read_particles();
    local.reset();
    engine_ = make_(params_);
    engine_->share_field(field_);
    engine_->add_particles(with_moved(std::move(ps), region, moved));
    return stalled;
  }

  /// Steps `e` until no pair is over the bound, the count of those stops
  /// falling, or the budget runs out; removes any the wall flagged outside.
  /// (`shown`: the sphere count for the progress lines.)
  bool relax_on(ParticleEngine& e, size_t shown) {
    // Near in space, near in memory (Engine::sort_by_cells): the pass-1
    // order, holes' newcomers at the end and the removals' swaps otherwise
    // scatter neighbours through memory, which costs most at large counts.
    e.sort_by_cells();
    if (s_.fire) e.restart_minimiser();  // from rest, at the first step, after the changes of the last round
    bool stalled = false;
    uint64_t done = 0;
    uint32_t pairs = 0, fewest = UINT32_MAX;
    int since_fewer = 0;
    while (done < s_.relax_steps) {
      if (s_.cancelled && s_.cancelled()) throw Cancelled();
      e.run_steps(static_cast<size_t>(s_.chunk_steps));
      done += static_cast<uint64_t>(s_.chunk_steps);
      stats_.steps += static_cast<uint64_t>(s_.chunk_steps);
      const std::vector<StepRecord> h = e.read_history();
      if (h.empty()) break;
      const StepRecord& last = h.back();
      pairs = last.colliding_pairs;  // pairs over the bound (the engine's spheres are smaller by it)
      // A relaxation of 1e6 spheres takes minutes on a CPU: report as it goes.
      if (progress_) progress_(shown, pairs);
      if (pairs == 0) break;
      // Stalled: the count over the bound has not fallen by `stall_fall` for `patience` reads.
      if (pairs < fewest - static_cast<uint32_t>(s_.stall_fall * fewest)) {
        fewest = pairs;
        since_fewer = 0;
      } else if (++since_fewer >= s_.patience) {
        stalled = true;
        break;
      }
    }
    std::vector<size_t> out = e.flagged_particles();
    e.clear_flags();
    if (!out.empty()) {
      stats_.removed += out.size();
      e.remove_particles(out);
    }
    if (progress_) progress_(shown - out.size(), pairs);
    return stalled;
  }

  /// After a stalled relaxation: the spheres pressed hardest go, about
  /// `fire_removal_share` (FIRE) or `removal_share` (damped) of the excess
  /// the overlaps imply (shrinking a sphere's radius by s of r frees 3 s of
  /// its volume; a sphere needs to shrink by half its worst excess overlap),
  /// and no two that overlap each other in one round (removing one relieves
  /// its neighbours).
  void remove_most_compressed(const ParticleSet& now, const std::vector<Overlap>& overlaps) {
    const size_t n = now.size();
    std::vector<double> need(n, 0), pressed(n, 0);
    const OverlapPartners touching(n, overlaps);
    for (const Overlap& o : overlaps) {
      const double excess = 0.5 * std::max(0.0, o.fraction - s_.max_overlap);
      need[o.i] = std::max(need[o.i], excess);
      need[o.j] = std::max(need[o.j], excess);
      pressed[o.i] += o.fraction;
      pressed[o.j] += o.fraction;
    }
    // Unequal spheres: the volume a sphere must give up, r_i^2 r_min need_i
    // (need_i a share of the smallest radius), counted in spheres of the
    // distribution's mean volume, as the deletions keep to it (counted in
    // smallest spheres, as for equal ones, 1:2 half-half deleted 4.5 times
    // too many small and twice too many large).
    const double mean_cube = sizes_ ? s_.sizes->mean_cube() : 0;
    double excess = 0;
    std::vector<size_t> candidates;
    for (size_t i = 0; i < n; ++i)
      if (need[i] > 0) {
        excess += sizes_ ? 3 * need[i] * now.radii[i] * now.radii[i] * s_.radius / mean_cube : 3 * need[i];
        candidates.push_back(i);
      }
    std::sort(candidates.begin(), candidates.end(),
              [&](size_t a, size_t b) { return pressed[a] > pressed[b] || (pressed[a] == pressed[b] && a < b); });
    // Jams (clusters of pairs over the bound) that the relaxation could not
    // undo lose their most pressed sphere, a share of them a round, so that
    // the rounds do not grow with the number of jams (that is, with N).
    std::vector<uint32_t> root(n);
    for (size_t i = 0; i < n; ++i) root[i] = static_cast<uint32_t>(i);
    auto find = [&](uint32_t i) {
      while (root[i] != i) i = root[i] = root[root[i]];
      return i;
    };
    for (const Overlap& o : overlaps)
      if (o.fraction > s_.max_overlap) root[find(o.i)] = find(o.j);
    std::vector<bool> blocked(n, false), jam_done(n, false), chosen(n, false);
    std::vector<size_t> out;
    // Unequal spheres: a class goes only while it keeps its share (the
    // large are the most pressed: deleting by pressure alone thinned them,
    // 1:2 half-half ended 60:40).
    if (sizes_) sizes_->recount(now.radii);
    auto may_go = [&](size_t i) { return !sizes_ || sizes_->may_lose(sizes_->class_of(now.radii[i])); };
    auto take = [&](size_t i) {
      if (sizes_) sizes_->remove(now.radii[i]);
      out.push_back(i);
      chosen[i] = true;
      jam_done[find(static_cast<uint32_t>(i))] = true;
      for (size_t k = touching.first[i]; k < touching.first[i + 1]; ++k) blocked[touching.partners[k]] = true;
    };
    // Only the most pressed jams, `jam_share` of them: removing a few
    // spheres relieves the pressure far around (the bunny: 14 removed
    // cleared 1,349 pairs over the bound), and one from every jam emptied
    // holes the packing could not fill again (0.584 against 0.592).
    std::vector<bool> counted(n, false);
    size_t jams = 0;
    for (size_t i : candidates) {
      const uint32_t r = find(static_cast<uint32_t>(i));
      if (!counted[r]) counted[r] = true, ++jams;
    }
    const size_t most = static_cast<size_t>(std::ceil(s_.jam_share * static_cast<double>(jams)));
    for (size_t i : candidates) {
      if (out.size() >= most) break;
      if (!jam_done[find(static_cast<uint32_t>(i))] && !blocked[i] && may_go(i)) take(i);
    }
    const double share = s_.fire ? s_.fire_removal_share : s_.removal_share;
    const size_t want = static_cast<size_t>(std::ceil(share * excess));
    for (size_t i : candidates) {
      if (out.size() >= want) break;
      if (!blocked[i] && !chosen[i] && may_go(i)) take(i);
    }
    stats_.removed += out.size();
    engine_->remove_particles(out);
  }

  /// Out of rounds: one sphere of every pair still over the bound goes
  /// (the more pressed one), so the bound holds whatever the rounds did.
  void remove_one_of_each(const ParticleSet& now, const std::vector<Overlap>& overlaps) {
    std::vector<double> pressed(now.size(), 0);
    for (const Overlap& o : overlaps) {
      pressed[o.i] += o.fraction;
      pressed[o.j] += o.fraction;
    }
    std::vector<bool> gone(now.size(), false);
    std::vector<size_t> out;
    for (const Overlap& o : overlaps) {
      if (o.fraction <= s_.max_overlap || gone[o.i] || gone[o.j]) continue;
      const size_t k = pressed[o.i] >= pressed[o.j] ? o.i : o.j;
      gone[k] = true;
      out.push_back(k);
    }
    stats_.removed += out.size();
    stats_.forced += out.size();
    engine_->remove_particles(out);
  }

  FinishSettings s_;
  const ScalarGrid& field_;
  FinishStats& stats_;
  double engine_radius_ = 0;  ///< the smallest's in the engine
  double shrink_ = 0;         ///< every engine sphere is smaller than its true radius by this
  std::optional<SizeDeficit> sizes_;
  std::mt19937_64 rng_{0x5eed};  ///< radii drawn inside a class (the same for the same packing)
  double deep_ = 0;  ///< how deep (by the field) a centre must lie
  uint64_t next_id_ = s_.first_id;  ///< the next inserted sphere's id
  std::unique_ptr<ParticleEngine> engine_;
  std::function<std::unique_ptr<ParticleEngine>(const EngineParams&)> make_;
  EngineParams params_;      ///< the relaxation's engines'
  std::vector<Vec3> hot_;    ///< where the last round's pairs over the bound lie (their midpoints)
  std::function<void(size_t, uint32_t)> progress_;
};

}  // namespace

double finish_inflation(double max_overlap) {
  // Tight bounds: pairs come to rest half the bound apart (plus a little for
  // rounding), so only pressure brings them over it. Loose bounds (1% of r and
  // more): pairs rest overlapping by 0.8 of the bound, which packs denser
  // (spot -n 4000, 5% bound: 0.644 against 0.623 at rest 2r).
  const double b = max_overlap;
  return 5e-5 + 0.5 * b - 0.9 * b * std::min(1.0, b / 0.01);
}

ParticleSet finish_packing(Device& device, const EngineParams& base, const ScalarGrid& field,
                           std::vector<Particle> particles, const FinishSettings& settings, FinishStats& stats,
                           const std::function<void(size_t, uint32_t)>& progress) {
  return finish_packing([&device](const EngineParams& p) { return std::make_unique<Engine>(device, p); }, base, field,
                        std::move(particles), settings, stats, progress);
}

ParticleSet finish_packing(const std::function<std::unique_ptr<ParticleEngine>(const EngineParams&)>& make,
                           const EngineParams& base, const ScalarGrid& field, std::vector<Particle> particles,
                           const FinishSettings& settings, FinishStats& stats,
                           const std::function<void(size_t, uint32_t)>& progress) {
  Finisher f(make, base, field, settings, stats);
  f.set_progress(progress);
  return f.run(std::move(particles));
}

}  // namespace pfill
