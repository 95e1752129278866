// Passes 1, 2 and the settle of DESIGN.md's algorithm, on any engine:
//   pass 1:  while not overfull: births at the sites; update
//   pass 2:  MaxParts = count - 1; top up to MaxParts
//   settle:  update until at rest
// With waves, the first births also go to room sites (FillOptions::
// room_spacing) wherever a newborn overlaps no sphere, until half of the
// expected count is in: the sparse start then takes a few hundred steps.
// The host runs a batch of steps (`sync_every`, or a wave's `birth_every`),
// then reads the step history and, while births may follow, a snapshot of
// the positions that the birth-room test uses; particles the wall flagged
// outside are removed then. Each newborn's draws come from a counter-based
// stream keyed by (seed, step, site) (counter_rng.hpp), and each site's room
// test runs on the process that decides it (site_verdicts.hpp): the same
// newborns on any engine and any MPI rank count. A wave of equal spheres is
// decided per process, each its own sites (wave_choice.hpp), and numbered
// in the processes' order; pass 2's capped waves are chosen alike on every
// process, each building only the newborns at the sites it decides. A wave
// of unequal spheres is walked alike on every process from each site's
// answer for every size class, given by the process that decides it
// (size_wave.cpp).
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "fill/fill_plan.hpp"
#include "fill/fill_progress.hpp"
#include "fill/held_sites.hpp"
#include "fill/large_first.hpp"
#include "fill/site_verdicts.hpp"
#include "fill/size_deficit.hpp"
#include "pfill/engine/particle_engine.hpp"
#include "pfill/fill.hpp"

namespace pfill {

class FillPasses {
 public:
  /// Runs on `engine` (empty, the field set); writes what the passes
  /// decide (stop signal, MaxParts, losses, pass times) into `result`.
  /// `sites`: the birth sites this process holds (held_sites.hpp), with
  /// the waves' room sites for the first births (may be none).
  FillPasses(ParticleEngine& engine, const FillOptions& o, const FillPlan& plan, HeldSites sites,
             FillReporter& reporter, FillResult& result);

  /// Unequal spheres with a rare large class (SizeDeficit::front_load):
  /// its quota placed at rest at deep points by `place` (large_first.hpp:
  /// on the field, or on candidates held per process), clear of the wall
  /// and of each other, before pass 1; a warning when fewer fit. Nothing
  /// for other fills.
  void place_large_first(const LargePlacer& place);
  void pass1();
  void pass2();
  void settle();

  /// The id the next particle gets (ids count births in order).
  uint64_t next_id() const { return next_id_; }
  /// Unequal spheres whose front-loaded class fell short: each class's
  /// most spheres (SizeDeficit::set_caps), for the finish; else empty.
  std::vector<size_t> size_caps() const { return sizes_ && sizes_->capped() ? sizes_->caps() : std::vector<size_t>{}; }
  /// "only N of the M largest spheres ... fit", when they fell short; else empty.
  const std::string& short_front() const { return short_front_; }
  /// Every process's birth sites (not the room sites), in key order, for
  /// the report (collective; split sites are gathered).
  std::vector<BirthSite> all_sites() { return pfill::all_sites(held_, engine_); }

 private:
  std::vector<int> run_batch(bool births);
  bool may_birth() const;
  void end_pass(FillPhase phase, uint64_t first_step, uint64_t rebuilds_before, double seconds);
  int birth_at_sites();
  int birth_wave();
  void take_birth_view();
  ParticleSet frame_particles();
  double birth_reach() const;
  bool room_births_due() const;
  int birth_wave_of_sizes();
  std::vector<SiteFits> size_fits() const;
  double class_radius(uint64_t site, size_t c) const;
  void count_sizes();
  void open_sites(bool rooms, std::vector<OpenSite>& open, std::vector<OpenSite>& room_open) const;
  std::vector<OpenSite> own_wave_sites(bool rooms);
  int add_own_wave(const std::vector<OpenSite>& mine);
  std::vector<OpenSite> wave_sites(bool capped, bool rooms);
  int add_wave(const std::vector<OpenSite>& chosen);
  Particle newborn_at(const Vec3& position, double radius, uint64_t site);
  Particle newborn(const Vec3& position, double radius, uint64_t site, uint64_t id) const;
  bool newborns_clear(const Vec3& site, double radius, double clearance) const;
  template <class HasRoom>
  double newborn_radius(const HasRoom& has_room, size_t site);
  void remove_newest();
  void follow_newest_through_removals(const std::vector<size_t>& removed);
  void renumber_along_cells();
  void throw_if_cancelled() const;

  ParticleEngine& engine_;
  const FillOptions& o_;
  const FillPlan& plan_;
  HeldSites held_;  ///< the sites (and the waves' room sites, for the first births) this process holds
  FillReporter& reporter_;
  FillResult& result_;
  double top_speed_ = 0;
  std::vector<StepRecord> history_;
  uint64_t rebuilds_ = 0;  ///< steps so far whose records say the lists were rebuilt
  std::vector<Vec3> snapshot_;   ///< positions at the last read, for the room tests (this process's view)
  /// The last read's view minus its centres and radii (moved to the
  /// snapshot): which sites this process decides (birth_view.hpp).
  BirthView view_;
  double view_reach_ = 0;          ///< the reach that view was taken with
  std::vector<double> snapshot_radii_;  ///< unequal spheres: their radii
  /// Unequal spheres: the size classes' counts, which choose each newborn's radius.
  std::optional<SizeDeficit> sizes_;
  struct Newborn {
    Vec3 position, velocity;
    uint64_t step;
    double radius;
  };
  std::vector<Newborn> newborns_;  ///< born since the last snapshot
  size_t newest_;                  ///< index of the last particle born (Engine::kGone: removed)
  uint64_t next_sort_ = 0;         ///< step of the next renumbering along the cells
  uint64_t next_id_ = 1;           ///< ids in birth order; the engines carry them (Particle::id)
  uint64_t last_frame_ = 0;
  std::string short_front_;  ///< place_large_first's shortfall, said in the final warning
};

}  // namespace pfill
