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
// spheres near them move, the engine holding the rest (ParticleEngine::hold;
// one that cannot, the C++ reference, relaxes them on an engine of their own): a
// relaxation of all N for a few hundred pairs cost spot at 1e6 a quarter
// of its fill.
// Holes the relaxed packing leaves get a sphere, relaxed in, while a
// round finds enough; then every hole a sphere fits without overlap gets
// one as it is. If the rounds run out, one sphere of each pair still over
// the bound goes, so the bound always holds.
//
// The device runs the relaxation; the host reads the step history every
// `chunk_steps` steps (a few scalars) and the positions once a relaxation.
// On an engine split over processes (LAMMPS at P > 1 ranks) each reads
// only its own spheres and a halo (finish_view.hpp) and decides the
// deletions and holes of its own (finish_removals.hpp); the counts that
// steer the rounds are summed over the processes. Unequal spheres' size
// classes are counted so too, and every process walks every process's
// holes alike to give them radii (hole_radii.hpp). Nothing is
// gathered: each process returns its own spheres.
#include "fill/finish.hpp"
#include "fill/finish_removals.hpp"
#include "fill/finish_view.hpp"
#include "fill/hole_radii.hpp"
#include "fill/near_region.hpp"
#include "fill/size_deficit.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

#include "pfill/error.hpp"
#include "pfill/exact_field.hpp"
#include "pfill/packing_metrics.hpp"
#include "pfill/sdf.hpp"
#include "pfill/voids.hpp"

namespace pfill {
namespace {

/// A held sphere's mass in a local relaxation: its speed stays 0 to float precision.
constexpr double kHeldMass = 1e30;

/// How far past its sub-domain a process sees (FinishView), in radii: two
/// contact distances, so that every partner of a halo sphere touching an
/// own one is in view (its pressure whole), plus LAMMPS' atoms' drift
/// past their sub-domain since the last exchange (under a radius).
constexpr double kViewReach = 4.5;

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
    if (s.inner_lists) p.inner_lists = InnerLists::on;  // (FinishSettings::inner_lists)
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
    give_wall(*engine_);
    group_ = engine_->process_group();
  }

  /// `share` empty (no total): `ps` is the whole set; else this process's
  /// share of the set.
  ParticleSet run(std::vector<Particle> ps, const SetShare& share) {
    if (s_.sizes) {
      sizes_.emplace(*s_.sizes);
      sizes_->set_caps(s_.size_caps);
    }
    upload(std::move(ps), share);
    int holes_done = 0;
    bool compressing = s_.compress_clearance > 0;
    size_t last_inserted = 0, deleted_since_insert = 0;
    for (int round = 0;; ++round) {
      const bool stalled = relax();
      look();
      const std::vector<Overlap> overlaps = find_overlaps(view_.set, 0.0);
      size_t over = 0;
      hot_.clear();
      for (const Overlap& o : overlaps)
        if (o.fraction > s_.max_overlap && view_.counts(o)) {
          ++over;
          hot_.push_back(0.5 * (view_.set.positions[o.i] + view_.set.positions[o.j]));
        }
      // What steers the rounds is counted over every process alike.
      over = total_over_processes(*engine_, view_, over);
      const double n = static_cast<double>(engine_->size());
      share_hot(over, n);
      if (over > 0) {
        if (round + 1 >= s_.max_rounds) {
          stats_.forced += remove(one_of_each_over(view_, overlaps, s_.max_overlap));
          break;
        }
        // Still falling when the steps ran out: relax on, delete nothing
        // (deleting then cost the bunny at r 0.012253, seed 1, 2% of its
        // packing); but a few pairs left that fall slowly go at once.
        if (!stalled && static_cast<double>(over) > s_.run_on_share * n) continue;
        // Compressing ends where it deletes half of what it inserts: the
        // packing is then as full as the bound allows.
        deleted_since_insert += remove(most_compressed_here(overlaps));
        if (2 * deleted_since_insert > last_inserted) compressing = false;
        continue;
      }
      if ((!compressing && holes_done >= s_.hole_rounds) || round + 1 >= s_.max_rounds) break;
      if (all_held(view_.set)) break;
      const double clearance = compressing ? s_.compress_clearance : s_.hole_clearance;
      std::vector<double> gaps;
      const std::vector<Vec3> holes =
          holes_decided_here(*engine_, view_,
                             holes_in(view_.set, clearance * s_.radius, sizes_ ? s_.radius : 0, &gaps, view_.mine()),
                             gaps, clearance * s_.radius);
      // A round of a few holes does not pay for its relaxation (each takes
      // about 1,500 steps to settle, whatever the number of newcomers): the
      // fit pass below takes those a sphere fits in as they are.
      if (static_cast<double>(total_over_processes(*engine_, view_, holes.size())) < s_.hole_round_share * n) {
        if (!compressing) break;
        compressing = false;  // compressed: the ordinary holes next
        continue;
      }
      if (!compressing) ++holes_done;
      hot_.clear();  // newcomers everywhere: the next relaxation is of all
      last_inserted = insert_into_holes(holes, gaps, clearance);
      deleted_since_insert = 0;
      // Every class held at its cap: no hole takes a sphere, and another round would only relax.
      if (last_inserted == 0 && sizes_ && sizes_->capped()) break;
    }
    ParticleSet now = add_fits();
    stats_.next_id = next_id_;
    return now;
  }

  void set_progress(const std::function<void(size_t, uint32_t)>& f) { progress_ = f; }

 private:
  /// The spheres onto the engine, at rest, at the engine's radius.
  void upload(std::vector<Particle> ps, const SetShare& share) {
    for (Particle& p : ps) {
      p.velocity = {};
      p.radius = sizes_ ? p.radius - shrink_ : engine_radius_;
      // One mass for all: the relaxation is a minimiser, and unequal masses
      // left the large spheres slow to give way.
      p.mass = 1;
    }
    if (share.total == 0) {
      engine_->add_particles(ps);
    } else {
      engine_->add_decided_particles(ps, places_of(share, ps.size()), share.total);
    }
  }

  /// A sphere into each of `holes` (the nearest centre `gaps` away), on
  /// the engine, for the next relaxation to make room for. Returns how
  /// many, over every process.
  size_t insert_into_holes(const std::vector<Vec3>& holes, const std::vector<double>& gaps, double clearance) {
    std::vector<double> radii(holes.size(), s_.radius);
    if (sizes_) {
      // Unequal spheres: as large as the hole takes at this clearance's
      // overlap (the same share of the radius as for the smallest), of
      // a class still short of its share.
      count_sizes(view_.set);
      std::vector<double> rooms(holes.size());
      for (size_t k = 0; k < holes.size(); ++k)
        rooms[k] = room_at(holes[k], s_.radius * (gaps[k] - s_.radius) / (clearance * s_.radius - s_.radius));
      radii = radii_walked_alike(*engine_, view_, rooms, *sizes_, rng_);
    }
    std::vector<Particle> newcomers;
    for (size_t k = 0; k < holes.size(); ++k) {
      if (radii[k] <= 0) continue;
      Particle p;
      p.position = holes[k];
      p.radius = radii[k] - shrink_;
      p.mass = 1;
      newcomers.push_back(p);
    }
    return add_newcomers(newcomers);
  }

  /// Newcomers onto the engine, numbered from next_id_ over every process
  /// in order; returns how many over all.
  size_t add_newcomers(std::vector<Particle>& newcomers) {
    const SetShare share = batch_ids(*engine_, view_, newcomers, next_id_);
    if (view_.complete()) {
      engine_->add_particles(newcomers);
    } else {
      engine_->add_decided_particles(newcomers, places_of(share, newcomers.size()), share.total);
    }
    stats_.inserted += share.total;
    return share.total;
  }

  /// After the last relaxation: holes a sphere fits in without overlap (a
  /// deletion after the last insertion may leave one) take one as they
  /// are: nothing to relax. Returns every sphere.
  ParticleSet add_fits() {
    if (!view_.complete()) return add_fits_per_process();
    view_ = FinishView();
    ParticleSet now = current();
    if (all_held(now)) return now;
    std::vector<double> gaps;
    const std::vector<Vec3> fits =
        s_.hole_rounds > 0
            ? holes_in(now, s_.fit_clearance * s_.radius * (1 + 1e-6), sizes_ ? s_.radius : 0, &gaps, nullptr)
            : std::vector<Vec3>{};
    if (sizes_) count_sizes(now);
    const std::vector<double> radii = fit_radii(fits, gaps);
    for (size_t k = 0; k < fits.size(); ++k) {
      if (radii[k] <= 0) continue;
      now.positions.push_back(fits[k]);
      now.radii.push_back(radii[k]);
      now.ids.push_back(next_id_++);
      now.velocities.push_back({});
      ++stats_.inserted;
    }
    return now;
  }

  /// The same per sub-domain: each process's fits, apart from those
  /// across its borders, onto the engine; then its own spheres.
  ParticleSet add_fits_per_process() {
    look();
    const double clearance = s_.fit_clearance * s_.radius;
    std::vector<double> gaps;
    const std::vector<Vec3> fits =
        s_.hole_rounds > 0 && !all_held(view_.set)
            ? holes_decided_here(
                  *engine_, view_,
                  holes_in(view_.set, clearance * (1 + 1e-6), sizes_ ? s_.radius : 0, &gaps, view_.mine()), gaps,
                  clearance)
            : std::vector<Vec3>{};
    if (sizes_) count_sizes(view_.set);
    const std::vector<double> radii = fit_radii(fits, gaps);
    std::vector<Particle> newcomers;
    for (size_t k = 0; k < fits.size(); ++k) {
      if (radii[k] <= 0) continue;
      newcomers.emplace_back();
      newcomers.back().position = fits[k], newcomers.back().radius = radii[k] - shrink_;
    }
    add_newcomers(newcomers);
    view_ = FinishView();
    // The result stays in parts: this rank's own spheres, and where each rank's lie.
    LocalView mine = engine_->local_view(0);
    mine.particles.resize(mine.own);
    stats_.regions = std::move(mine.regions);
    stats_.region = mine.region;
    return at_true_radii(mine.particles, s_.radius, shrink_, sizes_.has_value());
  }

  /// Unequal spheres: the classes' counts of every process's own spheres
  /// (`set`: the view's, own first; with the view complete, all of it).
  void count_sizes(const ParticleSet& set) {
    sizes_->recount(set.radii, view_.complete() ? set.size() : view_.own, *group_);
  }

  /// Unequal spheres held to caps (FinishSettings::size_caps), every class
  /// at its cap: no hole may take a sphere, and a search of a loose
  /// packing's many holes would take long for nothing.
  /// (`now`: the view's spheres, own first; collective.)
  bool all_held(const ParticleSet& now) {
    if (!sizes_ || !sizes_->capped()) return false;
    count_sizes(now);
    return sizes_->all_capped();
  }

  /// The spheres now, at their true radii: every one.
  ParticleSet current() const {
    return at_true_radii(engine_->read_particles(), s_.radius, shrink_, sizes_.has_value());
  }

  /// What this process decides the next round on (finish_view.hpp).
  void look() {
    view_ = FinishView();  // (memory: the last round's view goes before this one's is read)
    const double largest = s_.sizes ? std::max(s_.radius, s_.sizes->max_radius()) : s_.radius;
    view_ = finish_view(*engine_, kViewReach * largest, s_.radius, shrink_, sizes_.has_value());
    stats_.largest_view = std::max(stats_.largest_view, view_.set.size());
  }

  /// Unequal spheres: the largest radius a hole at `p` may take, at most
  /// `room`, and deep enough inside by the wall.
  double room_at(const Vec3& p, double room) const {
    const double depth = -(s_.wall ? s_.wall->at(p) : sample(field_, p));
    return std::min(room, depth / (1 + s_.wall_margin));
  }

  /// The radius each of this process's `fits` (the nearest centre `gaps`
  /// away) gets as it is: equal spheres `radius`; unequal, no larger than
  /// the gap to the nearest sphere, nor than to the fits placed before it
  /// (each counted as the smallest), nor than its depth allows
  /// (hole_radii.hpp). 0: none fits.
  std::vector<double> fit_radii(const std::vector<Vec3>& fits, const std::vector<double>& gaps) {
    if (!sizes_) return std::vector<double>(fits.size(), s_.radius);
    std::vector<double> rooms(fits.size());
    for (size_t k = 0; k < fits.size(); ++k) rooms[k] = room_at(fits[k], gaps[k] - s_.radius);
    return fit_radii_walked_alike(*engine_, view_, fits, rooms, *sizes_, rng_);
  }

  /// A relaxation: of the spheres near the last round's pairs over the
  /// bound (`hot_`) where they are few (relax_held, relax_near), else of all.
  bool relax() {
    ++stats_.rounds;
    if (!hot_.empty() && engine_->size() >= s_.near_min_spheres) {
      // (held at least a pair's reach deep: an engine's hold leaves out the rest's pairs)
      const EngineConstants& c = engine_->constants();
      const double hold = std::max(s_.near_hold * s_.radius, c.list_reach - c.skin);
      const NearParts part_of(hot_, s_.near_reach * s_.radius, hold);
      // (by reference: the places' grid is not copied)
      if (const std::optional<size_t> taking_part = engine_->hold(std::cref(part_of)))
        return relax_held(*taking_part);
      if (const std::optional<bool> stalled = relax_near(hold)) return *stalled;
    }
    return relax_on(*engine_, engine_->size());
  }

  /// Every process's pairs over the bound (`over` of them), for a local
  /// relaxation of their spheres: each process sees only those near its
  /// own. While they may be few enough (each has two moving spheres), all
  /// go to every process; else none.
  void share_hot(size_t over, double n) {
    if (view_.complete()) return;
    // (alike on every process: both counts are totals)
    if (n < static_cast<double>(s_.near_min_spheres) || 2.0 * static_cast<double>(over) > s_.near_share * n) {
      hot_.clear();
      return;
    }
    hot_ = places_everywhere(*engine_, std::move(hot_));
  }

  /// The relaxation of the engine's spheres near `hot_` where they are
  /// (the engine holds the others: ParticleEngine::hold), `taking_part`
  /// of them moving or held; of all where those are too many.
  bool relax_held(size_t taking_part) {
    const size_t n = engine_->size();
    const bool local = static_cast<double>(taking_part) <= s_.near_share * static_cast<double>(n);
    if (!local) engine_->release_hold();
    stats_.near_rounds += local ? 1 : 0;
    const bool stalled = relax_on(*engine_, n);
    if (local) engine_->release_hold();
    return stalled;
  }

  /// find_holes in `set`, at most one a sphere, `deep_` inside: by the
  /// mesh's exact distances where the engines' wall is the mesh's (the
  /// field is then coarser), else by the field.
  std::vector<Vec3> holes_in(const ParticleSet& set, double clearance, double reference_radius,
                             std::vector<double>* gaps, const Box3* within) const {
    if (s_.wall)
      return find_holes(set, field_, [this](const Vec3& p) { return s_.wall->at(p); }, deep_, clearance, set.size(),
                        reference_radius, gaps, within);
    return find_holes(set, field_, deep_, clearance, set.size(), reference_radius, gaps, within);
  }

  /// The wall for a new engine: the field (it outlives the engine), or the mesh's exact one.
  void give_wall(ParticleEngine& e) const {
    if (s_.wall)
      e.share_exact_field(*s_.wall);
    else
      e.share_field(field_);
  }

  /// For an engine that cannot hold (the C++ reference engine): relaxes only the
  /// spheres within `near_reach` r of a place in `hot_`,
  /// with those up to `hold` further held still (as good as infinite
  /// mass), on an engine of their own; then the main engine takes them
  /// back. One engine at a time: each holds a cell grid over the field's
  /// whole box (~550 MiB at 1e6), and two at once took the peak from 1,645
  /// to 2,166 MiB. Nothing (no relaxation) when the region holds more than
  /// `near_share` of the spheres: a relaxation of all then costs little more.
  std::optional<bool> relax_near(double hold) {
    std::vector<Particle> ps = engine_->read_particles();
    const NearRegion region = region_near(ps, hot_, s_.near_reach * s_.radius, hold);
    if (static_cast<double>(region.moving.size() + region.held.size()) >
        s_.near_share * static_cast<double>(ps.size()))
      return std::nullopt;
    ++stats_.near_rounds;
    engine_.reset();
    std::unique_ptr<ParticleEngine> local = make_(params_);
    give_wall(*local);
    local->add_particles(region_particles(ps, region, kHeldMass));
    const bool stalled = relax_on(*local, ps.size());
    const std::vector<Particle> moved = local->read_particles();
    local.reset();
    engine_ = make_(params_);
    give_wall(*engine_);
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

  /// This process's deletions after a stalled relaxation (view indices):
  /// most_compressed; unequal spheres split over processes, only those the
  /// classes' shares allow with every process's picks.
  std::vector<size_t> most_compressed_here(const std::vector<Overlap>& overlaps) {
    if (sizes_) count_sizes(view_.set);
    const std::optional<SizeDeficit> counted = sizes_;  // (most_compressed lowers the counts by its picks)
    const std::vector<size_t> picked = most_compressed(view_, overlaps, removal_rule());
    if (!sizes_ || view_.complete()) return picked;
    sizes_ = counted;
    return picks_the_classes_allow(*engine_, view_, overlaps, picked, *sizes_);
  }

  /// The deletions after a stalled relaxation (finish_removals.hpp).
  RemovalRule removal_rule() {
    RemovalRule rule;
    rule.max_overlap = s_.max_overlap;
    rule.jam_share = s_.jam_share;
    rule.share = s_.fire ? s_.fire_removal_share : s_.removal_share;
    rule.radius = s_.radius;
    if (sizes_) rule.sizes = &*sizes_, rule.mean_cube = s_.sizes->mean_cube();
    return rule;
  }

  /// Removes this process's `picked` (view indices) and every other
  /// process's from the engine; returns how many over all.
  size_t remove(const std::vector<size_t>& picked) {
    const std::vector<size_t> all = picked_everywhere(*engine_, view_, picked);
    stats_.removed += all.size();
    engine_->remove_particles(all);
    return all.size();
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
  std::shared_ptr<ProcessGroup> group_;  ///< the processes the engines share (size classes' counts)
  std::function<std::unique_ptr<ParticleEngine>(const EngineParams&)> make_;
  EngineParams params_;      ///< the relaxation's engines'
  std::vector<Vec3> hot_;    ///< the midpoints of the last round's pairs over the bound, all processes' (share_hot)
  FinishView view_;          ///< what this process decides the round on
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
  return f.run(std::move(particles), {});
}

ParticleSet finish_packing(const std::function<std::unique_ptr<ParticleEngine>(const EngineParams&)>& make,
                           const EngineParams& base, const ScalarGrid& field, std::vector<Particle> mine,
                           const SetShare& share, const FinishSettings& settings, FinishStats& stats,
                           const std::function<void(size_t, uint32_t)>& progress) {
  Finisher f(make, base, field, settings, stats);
  f.set_progress(progress);
  return f.run(std::move(mine), share);
}

}  // namespace pfill
