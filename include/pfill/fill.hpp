/// @file fill.hpp
/// @brief The fill: a closed mesh in, a dense set of spheres out, by the
/// physics method of DESIGN.md (births inside at many sites, Lennard-Jones
/// pushes and inelastic collisions on the OpenCL engine, stop when overfull,
/// top up, settle, relieve overlaps, verify exactly).
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "pfill/birth_sites.hpp"
#include "pfill/colour.hpp"
#include "pfill/mesh.hpp"
#include "pfill/packing_metrics.hpp"
#include "pfill/particles.hpp"
#include "pfill/stop_tests.hpp"

namespace pfill {

class ParticleEngine;
struct EngineParams;

/// What a long fill reports while it runs (through FillOptions::progress).
struct FillProgress {
  std::string phase;            ///< "field", "pass 1", "pass 2", "settle", "finish", "verify"
  uint64_t step = 0;            ///< engine steps so far
  size_t particles = 0;
  size_t target = 0;            ///< the count expected when full (an estimate)
  double kinetic_energy = 0;
  uint32_t colliding_pairs = 0;
  double steps_per_second = 0;
  double elapsed = 0;           ///< seconds since the fill began
  double remaining = -1;        ///< estimated seconds left; < 0 when unknown
  size_t peak_memory = 0;       ///< the process's peak resident bytes so far (peak_resident_bytes)
};

struct FillOptions {
  // Density, as in the report: a radius, or a count that picks one.
  double radius = 0;            ///< particle radius in mesh units; 0: from `count`
  size_t count = 0;             ///< about this many particles (when radius is 0)
  double rest_distance = 1.0;   ///< potential minimum, in contact distances 2r (>= 1)

  // The potential and collisions.
  double epsilon = 1.0;
  double exponent_a = 12, exponent_b = 6;
  double cutoff = 0;            ///< in sigma; 0: purely repulsive (cut at the minimum)
  double restitution = 0.5;
  double wall_restitution = 0.5;
  double damping = 0;           ///< velocity damping rate during passes 1-2
  double time_step = 0.01;      ///< in units of the potential's time scale tau = sigma sqrt(m / eps)
  double max_step_fraction = 0.1;   ///< no particle moves more than this many sigma a step (the top speed)

  // Births. Two schedules (sites = -1, the default, picks waves from about
  // 2,000 particles on, where they are faster, and the report's 2 sites
  // below, where they pack denser and the fill takes seconds anyway):
  // - waves (sites = 0): sites spread over the whole interior,
  //   one per ~site_spacing^3 of volume, so their number grows with the
  //   count and pass 1 takes about as many steps at any size; every
  //   `birth_every` steps each site with room gets a newborn (one wave).
  // - the report's (sites >= 1): the deepest point, then far deep points
  //   (`--sites 1 --birth-every 1` is the report's single birth point).
  int sites = -1;               ///< -1: automatic; 0: waves over spread sites; N >= 1: N deepest, far-apart sites
  double site_depth_share = 0.75;  ///< sites >= 1: sites after the first are at least this share of the deepest depth
  int birth_every = 0;          ///< steps between birth attempts at each site; 0: 3 (sites >= 1) or 48 (waves)
  double site_spacing = 5;      ///< waves: sites at least this many rest distances (2r) apart
  double site_min_depth = 2;    ///< waves: sites at least this many radii inside
  std::optional<Vec3> birth_point;  ///< overrides the first site
  double birth_speed_min = 0.3; ///< newborn speed range, as fractions of the top speed
  double birth_speed_max = 0.6;
  /// A site has room when no centre is within this many rest distances (2r
  /// by default); 0: automatic, 0.5 for the report's schedule (measured on
  /// spot and a torus: densest) and 0.55 for waves (0.5 over many sites
  /// overfills, and relief then deletes more than it gained).
  double birth_clearance = 0;
  uint64_t seed = 1;

  // Pass 1 stopping.
  StopCriterion stop = StopCriterion::Blocked;
  KineticEnergySettings ke;
  CollisionCountSettings collisions;
  BlockedSitesSettings blocked;
  /// Waves: pass 1 also ends when the births of the last `blocked.patience`
  /// steps are at most this share of the particles. -1: automatic, 3% under
  /// a bound (max_overlap) below 1% of r, where later births only overfill
  /// what the finish then deletes (spot -n 100000: 0.6268 against 0.6254 at
  /// 1%, in 19% fewer steps), and 0.3% at looser bounds, where the overfill
  /// is the density (spot -n 16000 at 5%: 0.647 against 0.640 at 1%).
  double birth_stop_share = -1;
  uint64_t max_steps = 0;       ///< step budget of pass 1; 0: 100 per expected particle + 20,000

  // Pass 2 and settling.
  int top_up_patience = 1500;   ///< pass 2 gives up after this many steps without a birth
  double rest_speed = 0.02;     ///< at rest: top speed below this fraction of the speed cap ...
  int rest_steps = 200;         ///< ... for this many steps
  uint64_t settle_budget = 2000;

  // The finish (src/fill/finish.cpp): overlaps relaxed away by moving
  // spheres, deletions only where that stalls, holes filled.
  double max_overlap = 0.001;   ///< bound on every pair's overlap after the finish, fraction of r (0: none, below 1e-4 r); README says why 0.1%
  double containment_tolerance = 0.01;  ///< allowed crossing of the surface, fraction of r
  int void_rounds = 3;          ///< rounds of inserting spheres into holes (0: none)
  double void_clearance = 0.95; ///< a hole takes a sphere when the nearest centre is this many rest distances away

  // Colour: from the surface (vertex colours, texture), by depth, none, or
  // one colour. Empty: surface when the mesh has colours, else none.
  std::optional<ColourOptions> colour;

  // Machinery.
  double field_spacing = 0.33;  ///< signed distance grid spacing, in radii
  size_t max_field_samples = size_t(1) << 26;  ///< coarser spacing beyond this
  double skin = 0;              ///< neighbour-list skin, in sigma (lists rebuild when a particle moved half of it); 0: the step form's automatic one (kCpuFormSkinSigma 0.5, kGpuFormSkinSigma 0.3)
  int sync_every = 8;           ///< steps between reads of the step history
  int sort_every = 256;         ///< steps between renumberings of the particles along the cells (0: never); every 256 rather than 1,024: pass 1 of spot -n 16000 took 15% less kernel time a step
  std::string device;           ///< OpenCL device spec (index or name); "" = default
  std::function<void(const FillProgress&)> progress;
  /// Called with a line of what the fill chose for itself, e.g. the
  /// engine's automatic settings for the device (DeviceChoices::describe).
  std::function<void(const std::string&)> log;
  /// The engine passes 1-3 run on; empty: the OpenCL Engine on `device`.
  /// Given one (e.g. the C++ ReferenceEngine, for tests without an OpenCL
  /// device), no device is opened and the finish, which needs the OpenCL
  /// engine, is left out: the result is the settled packing, repaired for
  /// containment and measured.
  std::function<std::unique_ptr<ParticleEngine>(const EngineParams&)> engine;
  /// With `engine`: the finish runs on engines it makes too (the LAMMPS
  /// engine), instead of being left out.
  bool finish_on_engine = false;
  /// Called with a snapshot every `frame_every` steps (for --frames).
  std::function<void(uint64_t step, const ParticleSet&)> on_frame;
  uint64_t frame_every = 0;
  /// Polled once the distance field is built, then at every host sync
  /// (every `sync_every` steps, each relief round); when it returns true
  /// the fill throws pfill::Cancelled. For Ctrl-C: cheap, must not throw.
  std::function<bool()> cancelled;
};

struct PassStats {
  std::string name;
  uint64_t steps = 0;
  double seconds = 0;
};

struct FillResult {
  ParticleSet particles;
  PackingMetrics metrics;
  double radius = 0;
  size_t expected = 0;          ///< count estimated from the volume before the fill
  size_t max_parts = 0;         ///< MaxParts: the count at overfull, less one
  std::string stop_signal;      ///< which test ended pass 1: blocked, ke, collisions, budget
  std::string stop_reason;      ///< one sentence on why
  std::string settle_reason;
  size_t lost_outside = 0;      ///< particles the boundary kernel flagged outside and removed
  size_t ke_events = 0, collision_events = 0;
  size_t relief_removed = 0;    ///< deleted by the finish: no arrangement met the bound there (and any flagged outside)
  size_t relief_forced = 0;     ///< of those: one of each pair still over the bound when the finish's rounds ran out
  size_t relief_rounds = 0;     ///< the finish's relaxations
  size_t voids_filled = 0;      ///< spheres the finish inserted into holes (some may have gone again)
  ContainmentRepair containment;
  std::vector<PassStats> passes;
  std::vector<BirthSite> sites;
  double field_seconds = 0;
  size_t field_bytes = 0;
  double field_spacing = 0;
  std::string device;
  double seconds = 0;
  uint64_t steps = 0;
  /// The process's peak resident bytes when the fill ended (peak_resident_bytes:
  /// on PoCL the device's buffers included; 0 where the platform does not say).
  size_t peak_memory = 0;
  std::vector<std::string> warnings;  ///< about the mesh (open, inside-out)
};

/// Fills `mesh`. Throws pfill::Error with a one-line message for bad
/// settings, a radius that does not fit, or a device that cannot hold it;
/// pfill::Cancelled when FillOptions::cancelled returns true.
FillResult fill(const Mesh& mesh, const FillOptions& options);

/// Radius that gives about `count` particles in `volume` (enclosed by a
/// surface of `area`: spheres pack looser along it) for a physics fill
/// whose overlaps are bounded by `max_overlap` (a fraction of r; looser
/// bounds pack denser).
double fill_radius_for_count(double volume, double area, size_t count, double max_overlap = 0.001);

}  // namespace pfill
