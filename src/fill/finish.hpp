// The finish: from a settled, over-full packing (overlaps up to ~20% r) to
// one whose largest overlap is under a bound, by moving spheres rather than
// deleting them (see finish.cpp).
#pragma once
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "fill/finish_view.hpp"
#include "pfill/engine/engine.hpp"
#include "pfill/grid.hpp"
#include "pfill/particles.hpp"
#include "pfill/radius_distribution.hpp"

namespace pfill {

class Device;

struct FinishSettings {
  double radius = 0;            ///< the spheres' radius (unequal spheres: the smallest)
  /// Unequal spheres: their distribution (mesh units), which holes' spheres
  /// keep to (SizeDeficit); every bound is then of the pair's smaller radius,
  /// kept by measuring it at the smallest (the engine's spheres are all
  /// smaller by the same length). Empty: all of `radius`.
  std::optional<RadiusDistribution> sizes;
  /// Unequal spheres: each class's most spheres (SizeDeficit::set_caps),
  /// where the largest fell short of their quota; empty: none.
  std::vector<size_t> size_caps;
  double max_overlap = 0.001;   ///< bound on every pair's overlap, fraction of r
  double inflation = std::nan("");  ///< contact distance while relaxing: 2r (1 + inflation); NaN: automatic (finish_inflation)
  double time_step = 0.03;      ///< damped relaxation's step, in tau of the inflated potential
  /// The relaxation's integrator: FIRE (EngineParams::fire; every engine
  /// runs it), or, false, damped dynamics (`damping`; the fill uses it
  /// while compressing and for unequal spheres).
  bool fire = true;
  /// FIRE's first step, in tau, and its largest, in units of the first:
  /// 0.08 tau at most (from a first step of 0.03 tau the stiff cores of
  /// overlapping pairs restarted it every few steps; see docs/finish.md).
  double fire_time_step = 0.01;
  double fire_dt_max = 8;
  /// The relaxation's engine prunes inner lists (EngineParams::inner_lists,
  /// the `cpu` form's): its spheres move little, so a pruning is rarely due
  /// and the pair loop reads the few partners in contact, not every entry
  /// within the skin. The same spheres either way, faster, for a second
  /// buffer bounded at the inner reach (EngineConstants::inner_capacity:
  /// ~120 MiB more at 1e6).
  bool inner_lists = true;
  double damping = 0.01;        ///< damped dynamics: share of every velocity lost each step (little: inertia crosses the soft modes faster)
  int chunk_steps = 100;        ///< relaxation steps between reads of the step history
  uint64_t relax_steps = 1500;  ///< most steps of one relaxation (it stops earlier when the spheres stall; one still improving at the end runs again, a round of its own)
  int patience = 5;             ///< a relaxation has stalled when the pairs over the bound fell by under `stall_fall` in this many reads
  double stall_fall = 0.125;    ///< share; a slower creep (~9% in 500 steps) ends far sooner by a few deletions
  double run_on_share = 0.05;   ///< a relaxation out of steps while still falling runs on, while the pairs over the bound are this share of the spheres
  double jam_share = 0.1;       ///< after a stall, the most pressed of this share of the jams lose a sphere each (plus `removal_share` or, under FIRE, `fire_removal_share` of the excess)
  int max_rounds = 30;          ///< relaxations, each followed by removals or insertions
  double removal_share = 0.5;   ///< share of the estimated excess removed after a jammed relaxation (damped)
  /// The same under FIRE. FIRE stalls at the jammed state, where the
  /// estimate falls short of what must go (spot -n 4000, seed 1: 71
  /// estimated at the first stall, 92 deleted in all): all of it (1) took
  /// 13% fewer finish steps at -n 4000 (seeds 1-10) but 35% more at 1e5
  /// (7,700 -> 10,400), so the default stays at half (docs/finish.md).
  double fire_removal_share = 0.5;
  /// The last jams relax on their own (finish.cpp relax_near): the spheres
  /// within `near_reach` r of a pair over the bound move, those up to
  /// `near_hold` r further are held still, when all of them are at most
  /// `near_share` of the spheres (0: every relaxation is of all), and only
  /// from `near_min_spheres` on: below, a relaxation of all is cheap, and
  /// the held shell's extra deletions cost the report's schedule on the
  /// bunny 15 spheres (4,024 -> 4,009 at the 5% bound).
  double near_share = 0.25;
  size_t near_min_spheres = 100000;
  double near_reach = 6;
  double near_hold = 3;
  double hole_clearance = 1.9;  ///< a hole takes a sphere where the nearest centre is this many r away
  int hole_rounds = 3;          ///< rounds of insertions into holes (0: none, not even where a sphere fits)
  /// A loose packing (pass 1 ended by the report's own tests, which fire
  /// before the object is full) is first compressed: holes where the nearest
  /// centre is this many r away take a sphere, which the relaxation then
  /// makes room for, round after round while no relaxation stalls over the
  /// bound and a round finds holes for `hole_round_share` of the spheres.
  /// 0: no compression. (The bunny with the report's schedule: 0.526 without,
  /// 0.609 at 1.7 r, at the 5% bound; on a dense fill it only deletes.)
  double compress_clearance = 0;
  double hole_round_share = 0.005;  ///< a round of insertions runs only when it finds holes for this share of the spheres
  double fit_clearance = 2;     ///< then, a hole where the nearest centre is this many r away takes a sphere as it is
  uint64_t first_id = 1;        ///< ids given to the spheres inserted into holes, counting up (Particle::id)
  std::function<bool()> cancelled;  ///< polled at each read of the step history; true: throws pfill::Cancelled
  /// The engines' wall computed from the mesh (FillOptions::wall_from_mesh;
  /// it must outlive the finish); the field passed then only places holes.
  const ExactField* wall = nullptr;
  double wall_margin = 0.01;    ///< centres kept this many r further inside than the field says (bunny: 30 spheres the exact check removed at 0, none at 0.01)
};

struct FinishStats {
  size_t removed = 0;     ///< spheres deleted because no arrangement met the bound (and any the wall flagged outside)
  size_t inserted = 0;    ///< spheres inserted into holes (some may have been deleted again)
  size_t rounds = 0;      ///< relaxations
  size_t near_rounds = 0; ///< of those, of the spheres near the last jams only (FinishSettings::near_share)
  uint64_t steps = 0;     ///< relaxation steps
  size_t forced = 0;      ///< of `removed`: one of each pair still over the bound when the rounds ran out
  uint64_t next_id = 0;   ///< the id after the last one given to an inserted sphere
  /// The most spheres one process looked at in a round (its own and its
  /// halo; one process: every sphere). Issue 31: under the count at P > 1.
  size_t largest_view = 0;
  /// Where the result lies when each process returns its own spheres (the
  /// LAMMPS engine at P > 1): every process's region, in process order, and
  /// this one's; empty: one process, the result is every sphere.
  std::vector<Box3> regions;
  int region = 0;
};

/// Relaxes `particles` on a purely repulsive engine (FIRE, or damped) whose contact
/// distance is inflated by the bound (so a relaxed pair ends apart), with the
/// wall of `field`; deletes the most compressed spheres only when the
/// relaxation stalls with overlaps over the bound, inserts spheres into the
/// holes a sphere fits in, and returns the result. `base` supplies the
/// potential's shape and the device limits. `particles` is taken by value
/// (move it in: it is freed once on the device). `progress(n, overlapping pairs)`
/// is called after every read of the step history and every relaxation.
ParticleSet finish_packing(Device& device, const EngineParams& base, const ScalarGrid& field,
                           std::vector<Particle> particles, const FinishSettings& settings, FinishStats& stats,
                           const std::function<void(size_t, uint32_t)>& progress = {});

/// The same on engines that `make` builds (FillOptions::engine: e.g. the
/// LAMMPS engine) instead of the OpenCL Engine on a device.
ParticleSet finish_packing(const std::function<std::unique_ptr<ParticleEngine>(const EngineParams&)>& make,
                           const EngineParams& base, const ScalarGrid& field, std::vector<Particle> particles,
                           const FinishSettings& settings, FinishStats& stats,
                           const std::function<void(size_t, uint32_t)>& progress = {});

/// The same with the set split over the processes that share the engines
/// (issue 31: LAMMPS at P > 1 ranks): `mine` is this process's share of
/// the set, at `share`'s places, so no process is handed the whole set, nor
/// its ids.
ParticleSet finish_packing(const std::function<std::unique_ptr<ParticleEngine>(const EngineParams&)>& make,
                           const EngineParams& base, const ScalarGrid& field, std::vector<Particle> mine,
                           const SetShare& share, const FinishSettings& settings, FinishStats& stats,
                           const std::function<void(size_t, uint32_t)>& progress = {});

/// The automatic inflation for a bound (fraction of r): a relaxed pair
/// then sits at least the bound's half apart, well clear of it.
double finish_inflation(double max_overlap);

}  // namespace pfill
