// Passes 1, 2 and the settle (fill_passes.hpp).
#include "fill/fill_passes.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>

#include "fill/counter_rng.hpp"
#include "fill/large_first.hpp"
#include "fill/large_first_scale.hpp"
#include "pfill/count_rule.hpp"
#include "fill/particle_set_of.hpp"
#include "pfill/engine/engine.hpp"
#include "pfill/engine/local_view.hpp"
#include "pfill/error.hpp"
#include "pfill/particle_share.hpp"
#include "fill/short_number.hpp"
#include "fill/site_verdicts.hpp"
#include "fill/stopwatch.hpp"
#include "fill/wave_choice.hpp"

namespace pfill {
namespace {

// Room births end at this share of the expected count: past it the
// packing's structure forms, and births at the sites alone set it as
// before (a half, not a quarter, since 2026-12-06: as dense or denser from
// 4,000 to 1e5 over 3-6 seeds, 0.6334 at 1e6, and pass 1 16% shorter;
// docs/benchmarks.md). A room site takes a newborn only where no centre
// lies within this many rest distances, so that newborn overlaps nobody.
constexpr double kRoomUntil = 0.5, kRoomClearance = 1.0;
// Room sites at least this much further apart than their clearance (the
// choice keeps them a spacing apart by squared distances: a margin for the
// rounding) never crowd each other.
constexpr double kRoomSpacingApart = 1.001;

std::vector<size_t> take_flagged(ParticleEngine& e) {
  std::vector<size_t> out = e.flagged_particles();
  e.clear_flags();
  return out;
}

}  // namespace

FillPasses::FillPasses(ParticleEngine& engine, const FillOptions& o, const FillPlan& plan, HeldSites sites,
                       FillReporter& reporter, FillResult& result)
    : engine_(engine),
      o_(o),
      plan_(plan),
      held_(std::move(sites)),
      reporter_(reporter),
      result_(result),
      top_speed_(engine.constants().max_speed),
      newest_(Engine::kGone) {
  if (plan.sizes) {
    sizes_.emplace(*plan.sizes);
    sizes_->front_load(plan.expected, front_first_wave(plan, held_.total_sites));
  }
}

// ---- before pass 1: the rare large spheres, placed ----
void FillPasses::place_large_first(const LargePlacer& place) {
  if (!sizes_) return;
  // The radii large_first_scale tried (the same stream, on every process).
  const std::vector<double> radii = front_loaded_radii(plan_, held_.total_sites, o_.seed);
  if (radii.empty()) return;
  // Clear of the wall and of each other: every placed sphere starts with no force on it.
  const LargePlacement placed = place(radii, large_first_settings(plan_.radius));
  std::vector<Particle> ps;
  for (size_t k = 0; k < placed.centres.size(); ++k) {
    Particle p = newborn_at(placed.centres[k], placed.radii[k], held_.total_sites + held_.total_room_sites + k);
    p.velocity = Vec3();
    ps.push_back(p);
    sizes_->add(p.radius);
    snapshot_.push_back(p.position);
    snapshot_radii_.push_back(p.radius);
  }
  if (!ps.empty()) engine_.add_particles(ps);
  // Fewer fit than the quota: the other classes are held to their shares
  // of those placed, so that the fractions asked hold (the total falls).
  // (Radii shrunk below the count rule's: the other classes would fill the rest.)
  sizes_->set_caps(sizes_->caps_held_to_front(placed.radii, plan_.size_scale < 1));
  sizes_->end_front_load();
  if (placed.centres.size() < radii.size()) {
    short_front_ = "only " + std::to_string(placed.centres.size()) + " of the " + std::to_string(radii.size()) +
                   " largest spheres (radius up to " + short_number(radii.front()) + ") fit in the mesh";
    if (!sizes_->capped()) result_.warnings.push_back(short_front_ + ": that class ends short of its share");
  }
}

// ---- pass 1: births until the object is overfull ----
void FillPasses::pass1() {
  const Stopwatch t;
  const uint64_t first = engine_.steps_done(), rebuilds_before = rebuilds_;
  const uint64_t budget = o_.max_steps ? o_.max_steps : 100 * static_cast<uint64_t>(plan_.expected) + 20000;
  KineticEnergyTest ke(o_.ke);
  CollisionCountTest collisions(o_.collisions);
  // Over many sites a few keep finding room now and then long after the
  // object is full: waves end when births fall to a small share (3% under
  // a bound below 1% of r, where later births only overfill what the finish
  // deletes; 0.3% at looser bounds, where the overfill is the density).
  BlockedSitesSettings bs;
  bs.patience = plan_.patience;
  bs.share = !plan_.waves ? 0 : o_.stop_share >= 0 ? o_.stop_share : o_.max_overlap < 0.01 ? 0.03 : 0.003;
  BlockedSitesTest blocked(bs);
  // Waves of equal spheres under a tight bound end max_overfill over the
  // expected count (FillOptions::max_overfill; 0 here: no such end).
  const double overfill_cap = plan_.waves && !sizes_ && o_.max_overlap < 0.01 && o_.max_overfill >= 0
                                  ? (1 + o_.max_overfill) * plan_.expected
                                  : 0.0;
  reporter_.set_schedule(static_cast<size_t>(std::llround(plan_.expected)),
                         {plan_.waves, plan_.expected, static_cast<double>(bs.patience), bs.share,
                          static_cast<double>(o_.settle_steps)});
  reporter_.time_left().pass1_started(first);
  reporter_.enter(FillPhase::Pass1);
  auto stop = [&](const char* signal, std::string reason) {
    result_.stop_signal = signal;
    result_.stop_reason = std::move(reason);
  };
  // The first wave's view too (no particle yet): else it would be the
  // default, complete one, and every process would build that whole wave.
  if (!sizes_ || plan_.waves) take_birth_view();
  bool overfull = false;
  while (!overfull) {
    const std::vector<int> born = run_batch(!(ke.waiting() || collisions.waiting()));
    for (size_t k = 0; k < history_.size() && !overfull; ++k) {
      const int births = k < born.size() ? born[k] : 0;
      StopVerdict v = StopVerdict::Continue;
      if (o_.stop == StopCriterion::KineticEnergy) v = ke.observe(history_[k], births > 0);
      if (o_.stop == StopCriterion::Collisions) v = collisions.observe(history_[k], births > 0);
      if (v == StopVerdict::RemoveNewest) remove_newest();
      if (v == StopVerdict::Overfull) {
        overfull = true;
        stop(to_string(o_.stop), o_.stop == StopCriterion::KineticEnergy
                                     ? "the kinetic energy rose over " + std::to_string(o_.ke.rising_steps) +
                                           " steps " + std::to_string(ke.events()) + " times"
                                     : "the colliding-pair count stayed unchanged and could not be lowered after " +
                                           std::to_string(o_.collisions.max_tries) + " removals");
      }
      // Classes held to the placed large spheres' shares, all full: no birth may follow.
      if (!overfull && sizes_ && sizes_->all_capped()) {
        overfull = true;
        stop("blocked", "every size class reached its share of the largest spheres placed");
      }
      if (!overfull && overfill_cap > 0 && static_cast<double>(engine_.size()) >= overfill_cap) {
        overfull = true;
        stop("blocked", short_number(static_cast<double>(engine_.size())) + " particles, at least " +
                            short_number(100 * o_.max_overfill) + "% over the ~" + short_number(plan_.expected) +
                            " expected: later births would only overfill what the finish deletes");
      }
      // The blocked-sites test always runs: it ends the pass when the
      // report's tests never fire (a prototype found they rarely do).
      if (!overfull && blocked.observe(births, engine_.size()) == StopVerdict::Overfull) {
        overfull = true;
        stop("blocked", (blocked.steps_without_birth() >= bs.patience
                             ? "no birth site had room for " + std::to_string(bs.patience) + " steps"
                             : "the " + std::to_string(held_.total_sites) + " sites had room for at most " +
                                   short_number(bs.share * 100) + "% of the particles in the last " +
                                   std::to_string(bs.patience) + " steps") +
                            (o_.stop != StopCriterion::Blocked
                                 ? std::string(" (the ") + to_string(o_.stop) + " test did not fire first)"
                                 : ""));
      }
    }
    result_.ke_events = ke.events();
    result_.collision_events = collisions.tries();
    if (!overfull && engine_.steps_done() - first >= budget) {
      overfull = true;
      stop("budget", "the step budget of pass 1 (" + std::to_string(budget) + " steps) ran out");
    }
  }
  end_pass(FillPhase::Pass1, first, rebuilds_before, t.seconds());
  reporter_.time_left().pass1_ended();
}

// ---- pass 2: MaxParts = count - 1; top up to it ----
void FillPasses::pass2() {
  const Stopwatch t;
  const uint64_t first = engine_.steps_done(), rebuilds_before = rebuilds_;
  reporter_.enter(FillPhase::Pass2);
  result_.max_parts = engine_.size() > 0 ? engine_.size() - 1 : 0;
  if (engine_.size() > result_.max_parts && engine_.size() > 1) remove_newest();
  int idle = 0;
  while (engine_.size() < result_.max_parts && idle < o_.top_up_patience) {
    const std::vector<int> born = run_batch(true);
    const bool any = std::any_of(born.begin(), born.end(), [](int b) { return b > 0; });
    idle = any ? 0 : idle + static_cast<int>(born.size());
  }
  end_pass(FillPhase::Pass2, first, rebuilds_before, t.seconds());
}

// ---- settle: run until at rest ----
void FillPasses::settle() {
  const Stopwatch t;
  const uint64_t first = engine_.steps_done(), rebuilds_before = rebuilds_;
  reporter_.enter(FillPhase::Settle);
  reporter_.time_left().settle_started(first);
  int calm = 0;
  result_.settle_reason = "the step budget (" + std::to_string(o_.settle_steps) + " steps) ran out";
  while (engine_.steps_done() - first < o_.settle_steps) {
    run_batch(false);
    for (const StepRecord& r : history_) calm = r.max_speed < o_.rest_speed * top_speed_ ? calm + 1 : 0;
    if (calm >= o_.rest_steps) {
      result_.settle_reason = "at rest: every speed below " + short_number(o_.rest_speed) + " of the top speed for " +
                              std::to_string(o_.rest_steps) + " steps";
      break;
    }
  }
  end_pass(FillPhase::Settle, first, rebuilds_before, t.seconds());
}

/// Runs a batch of steps (with birth attempts when `births`), then reads
/// the history (and, while births may follow or a frame is due, a snapshot
/// of the positions), removes flagged particles, reports progress.
/// Returns, per step of the batch, how many particles were born before it.
std::vector<int> FillPasses::run_batch(bool births) {
  throw_if_cancelled();
  // Waves: one wave a batch, right after the snapshot it tests room on.
  const int steps = plan_.waves ? plan_.birth_every : o_.sync_every;
  std::vector<int> born(static_cast<size_t>(steps), 0);
  if (o_.sort_every > 0 && engine_.steps_done() >= next_sort_) renumber_along_cells();
  for (int s = 0; s < steps; ++s) {
    const bool due = plan_.waves ? s == 0 : engine_.steps_done() % static_cast<uint64_t>(plan_.birth_every) == 0;
    if (births && due && may_birth()) born[s] = plan_.waves ? birth_wave() : birth_at_sites();
    engine_.run_steps(1);
  }
  history_ = engine_.read_history();
  uint32_t flagged = 0;
  for (const StepRecord& r : history_) {
    flagged = std::max(flagged, r.flagged);
    rebuilds_ += r.lists_rebuilt;
  }
  if (flagged > 0) {
    const std::vector<size_t> out = take_flagged(engine_);
    result_.lost_outside += out.size();
    follow_newest_through_removals(out);
    engine_.remove_particles(out);
  }
  // Positions come back only for what needs them: the birth-room test and frames.
  const bool frame_due = o_.on_frame && o_.frame_every && engine_.steps_done() / o_.frame_every != last_frame_;
  const bool births_ahead = reporter_.phase() == FillPhase::Pass1 || reporter_.phase() == FillPhase::Pass2;
  if (births_ahead || frame_due) {  // (a hold on births may end next batch)
    if (frame_due) {
      last_frame_ = engine_.steps_done() / o_.frame_every;
      o_.on_frame(engine_.steps_done(), frame_particles());
    }
    take_birth_view();
  }
  if (!history_.empty())
    reporter_.report(engine_.size(), history_.back().kinetic_energy, history_.back().colliding_pairs,
                     engine_.steps_done(), 0);
  return born;
}

/// A pass's record: its steps, the lists rebuilt on them, its time.
void FillPasses::end_pass(FillPhase phase, uint64_t first_step, uint64_t rebuilds_before, double seconds) {
  PassStats p{to_string(phase), engine_.steps_done() - first_step, seconds};
  p.list_rebuilds = static_cast<int64_t>(rebuilds_ - rebuilds_before);
  result_.passes.push_back(p);
}

/// Pass 2 births only up to MaxParts.
bool FillPasses::may_birth() const {
  return reporter_.phase() != FillPhase::Pass2 || engine_.size() < result_.max_parts;
}

/// One newborn at each site with room; returns how many were born.
int FillPasses::birth_at_sites() {
  int born = 0;
  const double clearance = plan_.birth_clearance * plan_.rest_distance(o_);
  const std::vector<BirthSite>& sites = held_.sites;  // (the report's few sites: on every process)
  std::vector<int> verdicts(sites.size(), 0);
  if (!sizes_) {
    mark_sites_with_room(view_, sites, [&](const BirthSite& s) {
      return site_has_room(snapshot_, s.position, clearance) && !pocket_full(snapshot_, s, plan_.mean_radius);
    }, verdicts);
    share_verdicts(engine_, view_, verdicts);
  }
  for (size_t k = 0; k < sites.size(); ++k) {
    if (!may_birth()) break;
    const BirthSite& site = sites[k];
    double radius = plan_.radius;
    if (sizes_) {
      if (pocket_full(snapshot_, site, plan_.mean_radius)) continue;
      radius = newborn_radius([&](double r) {
        return site_has_room(snapshot_, snapshot_radii_, site.position, r, plan_.birth_clearance) &&
               newborns_clear(site.position, r, clearance);
      }, k);
      if (radius <= 0) continue;
    } else if (!verdicts[k] || !newborns_clear(site.position, radius, clearance)) {
      continue;
    }
    const Particle p = newborn_at(site.position, radius, k);
    newest_ = engine_.add_particle(p);
    newborns_.push_back({p.position, p.velocity, engine_.steps_done(), radius});
    ++born;
  }
  return born;
}

/// A wave: one newborn at every site with room in the snapshot just read
/// (a grid of it answers each site in O(1)), added in one upload. Sites lie
/// several rest distances apart, so newborns of one wave never crowd each
/// other. Returns how many were born.
int FillPasses::birth_wave() {
  if (sizes_) return birth_wave_of_sizes();
  const bool capped = reporter_.phase() == FillPhase::Pass2;
  const bool rooms = !capped && room_births_due();
  // Room sites spaced wider than their clearance never crowd each other,
  // so each process may decide its own (wave_choice.hpp; one process: always).
  if (!capped && (view_.complete() || !rooms || o_.room_spacing > kRoomSpacingApart * kRoomClearance))
    return add_own_wave(own_wave_sites(rooms));
  return add_wave(wave_sites(capped, rooms));
}

/// Equal spheres: this process's open wave sites and, when `rooms`, its
/// open room sites (each in key order), each site's room tested here.
void FillPasses::open_sites(bool rooms, std::vector<OpenSite>& open, std::vector<OpenSite>& room_open) const {
  const RoomGrid room(snapshot_, plan_.birth_clearance * plan_.rest_distance(o_));
  add_open_sites(view_, held_.sites, [&](size_t k) { return held_.key(k); }, [&](const BirthSite& s) {
    return room.has_room(s.position) && !room.pocket_full(s, plan_.mean_radius);
  }, open);
  if (!rooms) return;
  const RoomGrid clear(snapshot_, kRoomClearance * plan_.rest_distance(o_));
  add_open_sites(view_, held_.room_sites, [&](size_t k) { return held_.room_key(k); },
                 [&](const BirthSite& s) { return clear.has_room(s.position); },  // (until half: no pocket test)
                 room_open);
}

/// The wave's newborns this process decides (wave_choice.hpp): its open
/// wave sites, then its room sites clear of every open wave site, the
/// others' near its border told by one gather.
std::vector<OpenSite> FillPasses::own_wave_sites(bool rooms) {
  std::vector<OpenSite> open, room_open;
  open_sites(rooms, open, room_open);
  if (!rooms) return open;
  const double clearance = kRoomClearance * plan_.rest_distance(o_);
  std::vector<uint64_t> told = border_site_words(view_, open, clearance);
  if (!view_.complete()) engine_.gather_over_processes(told);
  return choose_wave(open, room_open, sites_of_words(told), clearance);
}

/// This process's newborns at `mine` (own_wave_sites), placed and numbered
/// after the processes before it (share_wave).
int FillPasses::add_own_wave(const std::vector<OpenSite>& mine) {
  const WaveShare share = share_wave(engine_, view_, mine);
  if (share.total == 0) return 0;
  std::vector<Particle> ps;
  std::vector<size_t> places;
  for (size_t k = 0; k < mine.size(); ++k) {
    ps.push_back(newborn(mine[k].position, plan_.radius, mine[k].key, next_id_ + share.first + k));
    places.push_back(share.first + k);
  }
  next_id_ += share.total;
  newest_ = engine_.add_decided_particles(ps, places, share.total) + share.newest;
  return static_cast<int>(share.total);
}

/// Equal spheres, where the wave's births must be chosen in key order over
/// every process (pass 2's cap; room sites that may crowd each other across
/// a border): every process's open sites gathered (site_verdicts.hpp), then
/// the same choice on every process.
std::vector<OpenSite> FillPasses::wave_sites(bool capped, bool rooms) {
  std::vector<OpenSite> open, room_open;
  open_sites(rooms, open, room_open);
  share_open_sites(engine_, view_, open);
  if (rooms) share_open_sites(engine_, view_, room_open);
  if (capped && engine_.size() + open.size() > result_.max_parts)
    open.resize(result_.max_parts > engine_.size() ? result_.max_parts - engine_.size() : 0);
  return choose_wave(open, room_open, {}, kRoomClearance * plan_.rest_distance(o_));
}

/// The wave's newborns at `chosen` (wave_sites): ids in that order on every
/// process, but each process builds and hands over only those at the sites
/// it decides (ParticleEngine::add_decided_particles), so that on LAMMPS
/// each rank creates only its own sub-domain's newborns. A newborn's id and
/// draws depend on its place in the wave and its site's key, not on the ranks.
int FillPasses::add_wave(const std::vector<OpenSite>& chosen) {
  if (chosen.empty()) return 0;
  std::vector<Particle> mine;
  std::vector<size_t> places;
  for (size_t j = 0; j < chosen.size(); ++j) {
    const Vec3& at = chosen[j].position;
    if (view_.decides(at)) mine.push_back(newborn(at, plan_.radius, chosen[j].key, next_id_ + j)), places.push_back(j);
  }
  next_id_ += chosen.size();
  newest_ = engine_.add_decided_particles(mine, places, chosen.size()) + chosen.size() - 1;
  return static_cast<int>(chosen.size());
}

/// Room births while the fill is sparse, where the last view reached far
/// enough for their room test (one process: always).
bool FillPasses::room_births_due() const {
  return held_.total_room_sites > 0 && static_cast<double>(engine_.size()) < kRoomUntil * plan_.expected &&
         (view_.complete() || view_reach_ >= kRoomClearance * plan_.rest_distance(o_));
}

/// How far from its sites a process must see for the next births' room
/// tests: the birth clearance, and the room sites' while those may birth.
double FillPasses::birth_reach() const {
  // (unequal spheres: a newborn of the largest radius against another)
  if (sizes_) return plan_.birth_clearance * 2 * plan_.max_radius;
  double share = plan_.birth_clearance;
  if (held_.total_room_sites > 0 && static_cast<double>(engine_.size()) < kRoomUntil * plan_.expected)
    share = std::max(share, kRoomClearance);
  return share * plan_.rest_distance(o_);
}

/// A frame's spheres: all of them; on the LAMMPS engine at P > 1 every
/// rank's own, gathered to the first only (rank 0 writes the frames, as it
/// writes one output file; collective: every rank takes each frame).
ParticleSet FillPasses::frame_particles() {
  const std::shared_ptr<ProcessGroup> group = engine_.process_group();
  if (group->alone()) return to_particle_set(engine_.read_particles());
  LocalView own = engine_.local_view(0);
  own.particles.resize(own.own);
  return gather_particles(*group, to_particle_set(own.particles));
}

/// The room tests' view of the particles (ParticleEngine::birth_view): on
/// the LAMMPS engine at P > 1 this rank's atoms and those within the reach
/// of its sub-domain; the report's schedule of unequal spheres, whose
/// births depend on each other in the sites' order, sees every particle
/// and decides every site.
void FillPasses::take_birth_view() {
  view_reach_ = birth_reach();
  view_ = engine_.birth_view(view_reach_, sizes_ && !plan_.waves);
  hand_over_sites(held_, engine_, view_);  // (split sites, when a balance moved the sub-domains)
  snapshot_ = std::move(view_.centres);
  snapshot_radii_.clear();
  if (sizes_) {
    snapshot_radii_ = std::move(view_.radii);
    count_sizes();
  }
  view_.radii.clear();
  newborns_.clear();
}

/// Unequal spheres: the radius of a newborn where `has_room(r)` says
/// whether one of radius r fits: the size classes furthest below their
/// shares first (SizeDeficit); 0 when none fits.
template <class HasRoom>
double FillPasses::newborn_radius(const HasRoom& has_room, size_t site) {
  // The radius' own stream of the site's draws (counter_rng.hpp), seeding
  // the generator SizeDeficit draws with.
  CounterRng draws(o_.seed, engine_.steps_done(), site, 1);
  std::mt19937_64 rng(draws());
  for (size_t k : sizes_->candidates()) {
    const double r = sizes_->draw(k, rng);
    if (has_room(r)) {
      sizes_->add(r);
      return r;
    }
  }
  return 0;
}

/// The newborn at the site keyed `site` (held_sites.hpp): its speed and
/// direction from the stream of (seed, this step, site).
Particle FillPasses::newborn_at(const Vec3& position, double radius, uint64_t site) {
  return newborn(position, radius, site, next_id_++);
}

/// The newborn at the site keyed `site` with id `id`.
Particle FillPasses::newborn(const Vec3& position, double radius, uint64_t site, uint64_t id) const {
  CounterRng draws(o_.seed, engine_.steps_done(), site);
  Particle p;
  p.position = position;
  p.radius = radius;
  p.id = id;
  const double speed = o_.birth_speed[0] + (o_.birth_speed[1] - o_.birth_speed[0]) * draws.uniform();
  p.velocity = draws.direction() * (top_speed_ * speed);
  return p;
}

/// Newborns since the last snapshot fly straight at their birth speed
/// (they are the fastest particles there): predicted, they need no read-back.
/// Unequal spheres: clear of each by the birth clearance of the pair's radii.
bool FillPasses::newborns_clear(const Vec3& site, double radius, double clearance) const {
  const double dt = engine_.constants().dt;
  for (const Newborn& b : newborns_) {
    const Vec3 now = b.position + b.velocity * (dt * static_cast<double>(engine_.steps_done() - b.step));
    const double reach = sizes_ ? plan_.birth_clearance * (radius + b.radius) : clearance;
    if (length(now - site) < reach) return false;
  }
  return true;
}

/// Removes the newest particle (the report's "remove the last born"); when
/// it is gone already (removed outside), the last index instead.
void FillPasses::remove_newest() {
  if (engine_.size() == 0) return;
  const size_t idx = newest_ < engine_.size() ? newest_ : engine_.size() - 1;
  follow_newest_through_removals({idx});
  engine_.remove_particles({idx});
}

/// Keeps newest_ pointing at the newest particle through removals.
void FillPasses::follow_newest_through_removals(const std::vector<size_t>& removed) {
  newest_ = Engine::index_after_removal(newest_, removed, engine_.size());
}

/// Renumbers the particles along the cells (Engine::sort_by_cells): births
/// scatter them through memory, and near in space near in memory makes
/// every kernel of a step read from cache.
void FillPasses::renumber_along_cells() {
  const std::vector<size_t> order = engine_.sort_by_cells();  // (empty: the indices stay)
  if (newest_ != Engine::kGone && !order.empty())
    newest_ = static_cast<size_t>(std::find(order.begin(), order.end(), newest_) - order.begin());
  next_sort_ = engine_.steps_done() + static_cast<uint64_t>(o_.sort_every);
}

/// The caller's cancel hook (FillOptions::cancelled), polled at each batch.
void FillPasses::throw_if_cancelled() const {
  if (o_.cancelled && o_.cancelled()) throw Cancelled();
}

}  // namespace pfill
