/// @file fill.hpp
/// @brief The fill: a closed mesh in, a dense set of spheres out, by the
/// physics method of DESIGN.md (births inside at many sites, Lennard-Jones
/// pushes and inelastic collisions on the OpenCL engine, stop when overfull,
/// top up, settle, relieve overlaps, verify exactly).
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "pfill/birth_sites.hpp"
#include "pfill/colour.hpp"
#include "pfill/count_rule.hpp"
#include "pfill/mesh.hpp"
#include "pfill/packing_metrics.hpp"
#include "pfill/particles.hpp"
#include "pfill/radius_distribution.hpp"
#include "pfill/stop_tests.hpp"

namespace pfill {

class ParticleEngine;
struct EngineParams;

/// The parts of a fill, in the order they run (DESIGN.md's algorithm).
enum class FillPhase { Field, Pass1, Pass2, Settle, Finish, Verify };

/// The phase's name as progress lines show it: "field", "pass 1", "pass 2",
/// "settle", "finish", "verify".
const char* to_string(FillPhase phase);

/// What a long fill reports while it runs (through FillOptions::progress).
struct FillProgress {
  FillPhase phase = FillPhase::Field;
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

/// A fill's settings. Each has one name: this field, the Python keyword
/// of pfill.fill() and, with dashes, the command-line flag (the table in
/// fill_settings.hpp, which parses and documents them). The first group is
/// what a user chooses; the tuning below changes how the fill gets there.
struct FillOptions {
  // ---- the user's: density, physics of the report, seed, device ----
  double radius = 0;            ///< particle radius in mesh units; 0: from `count`
  size_t count = 0;             ///< about this many particles (when radius is 0)
  /// Unequal spheres: the radii's distribution (`--radii SPEC`,
  /// radius_distribution.hpp). With `count` its radii are relative, scaled so
  /// that about `count` spheres fill the mesh; without, in mesh units. Every
  /// overlap bound is then a fraction of the pair's smaller radius. Empty:
  /// equal spheres of `radius`.
  std::optional<RadiusDistribution> radii;
  /// What a discrete SPEC's fractions are: by number (default) or by volume.
  FractionBasis radii_by = FractionBasis::Number;
  double max_overlap = 0.001;   ///< bound on every pair's overlap after the finish, fraction of r (0: none, below 1e-4 r)
  double rest_distance = 1.0;   ///< potential minimum, in contact distances 2r (>= 1; larger: sparser)
  double epsilon = 1.0;         ///< depth of the potential well
  std::array<double, 2> exponents{12, 6};  ///< the potential's exponents A > B > 0 (repulsive, attractive)
  double cutoff = 0;            ///< in sigma; 0: purely repulsive (cut at the minimum)
  double restitution = 0.5;     ///< particle-particle
  double wall_restitution = 0.5;  ///< particle-surface
  /// What ends pass 1: the blocked-sites test (default), or the report's
  /// kinetic-energy or collision-count test (then the finish compresses
  /// what they leave, as they fire before the object is full).
  StopCriterion stop = StopCriterion::Blocked;
  uint64_t seed = 1;
  /// Colour: from the surface (vertex colours, texture), by depth, none, or
  /// one colour. Empty: surface when the mesh has colours, else none.
  std::optional<ColourOptions> colour;
  std::string device;           ///< OpenCL device spec (index or name); "" = default

  // ---- tuning: the schedule of births ----
  // Two schedules (sites = -1, the default, picks waves from about 2,000
  // particles on, where they are faster, and the report's 2 sites below):
  // - waves (sites = 0): sites spread over the whole interior, one per
  //   ~site_spacing^3 of volume, so pass 1 takes about as many steps at any
  //   size; every `birth_every` steps each site with room gets a newborn.
  // - the report's (sites >= 1): the deepest point, then far deep points
  //   (`--sites 1 --birth-every 1` is the report's single birth point).
  int sites = -1;               ///< -1: automatic; 0: waves over spread sites; N >= 1: N deepest, far-apart sites
  double site_depth = 0.75;     ///< sites >= 1: sites after the first lie at least this share of the deepest depth inside
  double site_spacing = 5;      ///< waves: sites at least this many rest distances (2r) apart
  double site_min_depth = 2;    ///< waves: sites at least this many radii inside
  /// Waves: until half the expected count is in, births also at room sites
  /// this many rest distances apart, each where its newborn overlaps no
  /// sphere (the sparse start in a few hundred steps, not thousands); 0: none.
  double room_spacing = 1.5;
  int birth_every = 0;          ///< steps between birth attempts at each site; 0: 3 (sites >= 1) or 0.48 tau (waves: 24 steps of equal spheres, 48 of unequal)
  std::optional<Vec3> birth;    ///< overrides the first site (must lie r inside)
  std::array<double, 2> birth_speed{0.3, 0.6};  ///< newborn speed range, as fractions of the top speed
  /// A site has room when no centre is within this many rest distances; 0:
  /// automatic, 0.5 for the report's schedule and 0.55 for waves.
  double birth_clearance = 0;
  int patience = 0;             ///< steps without a birth at any site that mean the sites are blocked; 0: 15 tau (1,500 steps at the report's step, 750 at the waves' of equal spheres)
  /// Waves: pass 1 also ends when the births of the last `patience` steps
  /// are at most this share of the particles. -1: automatic, 3% under a
  /// bound below 1% of r (later births only overfill what the finish
  /// deletes), 0.3% at looser bounds (where the overfill is the density).
  double stop_share = -1;
  /// Waves of equal spheres under a bound below 1% of r: pass 1 also ends
  /// when the particles are this share over the expected count (the count
  /// asked for, or the one the radius gives). Past that, births only
  /// overfill what the finish deletes: spot -n 16000 ended pass 1 1.9%
  /// over and its finish deleted 119-234 spheres in 6,400-9,400 steps; held
  /// to 0.5% over, 6-24 in 2,000-3,700, as densely. -1: no such end.
  double max_overfill = 0.005;
  uint64_t max_steps = 0;       ///< step budget of pass 1; 0: 100 per expected particle + 20,000
  KineticEnergySettings ke;     ///< the report's kinetic-energy test (stop = ke)
  CollisionCountSettings collisions;  ///< the report's collision-count test (stop = collisions)

  // ---- tuning: the dynamics ----
  double damping = 0;           ///< velocity damping rate during passes 1-2
  /// Pass 1's and the settle's step, in units of the potential's time scale
  /// tau = sigma sqrt(m / eps); 0: 0.02 for waves of equal spheres, else 0.01 (the report's).
  double time_step = 0;
  double max_step = 0;          ///< top speed: no particle moves more than this many sigma a step; 0: 10 time_step (10 sigma per tau)
  int top_up_patience = 1500;   ///< pass 2 gives up after this many steps without a birth
  double rest_speed = 0.02;     ///< at rest: top speed below this fraction of the speed cap ...
  int rest_steps = 200;         ///< ... for this many steps
  uint64_t settle_steps = 2000; ///< most steps of the settle (it ends sooner at rest)

  // ---- tuning: the finish (src/fill/finish.cpp) ----
  double containment_tolerance = 0.01;  ///< allowed crossing of the surface, fraction of r
  int hole_rounds = 3;          ///< rounds of inserting spheres into empty pockets (0: none)
  double hole_clearance = 0.95; ///< a pocket takes a sphere when the nearest centre is this many rest distances away

  // ---- tuning: machinery ----
  double field_spacing = 0.33;  ///< signed distance grid spacing, in radii
  size_t max_field_samples = size_t(1) << 26;  ///< coarser spacing beyond this
  double skin = 0;              ///< neighbour-list skin, in sigma; 0: the step form's automatic one (on CPUs 0.9 for purely repulsive spheres while they are born (passes 1-2, the settle; radii 1:2 and wider throughout), else 0.5; 0.3 on GPUs)
  int sync_every = 8;           ///< steps between reads of the step history (the report's schedule)
  int sort_every = 256;         ///< steps between renumberings of the particles along the cells (0: never)

  // ---- hooks (C++ and Python callers) ----
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
  /// With `engine`: it computes the wall near its particles from the mesh
  /// (ParticleEngine::share_exact_field; the LAMMPS engine, where each MPI
  /// rank then holds only the bricks of the wall its spheres reach) instead
  /// of reading a whole field. Waves of equal spheres on a mesh of one
  /// part then build no field at all: each process chooses the birth
  /// sites of its own sub-domain from the mesh's exact distances, the same
  /// sites at any process count (src/fill/site_choice.hpp).
  /// Other fills build the fill's own field at twice the spacing (an
  /// eighth of the samples) for the sites, its samples freed once they
  /// are chosen. The finish's holes ask the mesh.
  bool wall_from_mesh = false;
  /// Called with a snapshot every `frame_every` steps (for --frames). On
  /// an engine shared by several processes (the LAMMPS engine at P > 1)
  /// every process is called at the same steps; the first (rank 0) gets
  /// every sphere, the others an empty set (each frame is gathered to the
  /// first only, as one output file is).
  std::function<void(uint64_t step, const ParticleSet&)> on_frame;
  uint64_t frame_every = 0;
  /// Polled once the distance field is built, then at every host sync
  /// (every `sync_every` steps, each relaxation); when it returns true the
  /// fill throws pfill::Cancelled. For Ctrl-C: cheap, must not throw.
  std::function<bool()> cancelled;
};

struct PassStats {
  std::string name;
  uint64_t steps = 0;
  double seconds = 0;
  /// With PFILL_PROFILE=1 in the environment (the OpenCL engine's queue
  /// then profiles every command): the device's time in kernels and in
  /// host-device transfers during the pass; the rest of `seconds` is the
  /// host's work between them. < 0 when not profiled.
  double kernel_seconds = -1;
  double transfer_seconds = -1;
  std::map<std::string, double> kernel_split{};  ///< profiled: kernel_seconds by kernel name
  /// Steps of the pass that rebuilt the neighbour lists (a rebuild costs a
  /// few plain steps: pass 1's rebuilds are a third of its kernel time at
  /// 1e5). Counted from the OpenCL engine's step records for passes 1, 2
  /// and the settle; -1 where not counted (the finish, whose FIRE record
  /// carries the power instead; other engines).
  int64_t list_rebuilds = -1;
};

struct FillResult {
  /// The spheres. On the LAMMPS engine at P > 1 MPI ranks, each rank's
  /// own (`in_parts`): those of its sub-domain, no rank all of them
  /// (gather_particles, particle_share.hpp, brings them to one); the
  /// metrics and counts below are of the whole on every rank.
  ParticleSet particles;
  bool in_parts = false;  ///< `particles` is this process's part of the result, not all of it
  PackingMetrics metrics;
  double radius = 0;            ///< equal spheres: their radius; unequal: the smallest the distribution draws
  /// Unequal spheres: the distribution in mesh units (scaled to the count),
  /// and how the spheres of the result follow it.
  std::optional<RadiusDistribution> radii;
  std::optional<DistributionFit> radii_fit;
  size_t expected = 0;          ///< count estimated from the volume before the fill
  size_t max_parts = 0;         ///< MaxParts: the count at overfull, less one
  std::string stop_signal;      ///< which test ended pass 1: blocked, ke, collisions, budget
  std::string stop_reason;      ///< one sentence on why
  std::string settle_reason;
  size_t lost_outside = 0;      ///< particles the boundary kernel flagged outside and removed
  size_t ke_events = 0, collision_events = 0;
  size_t finish_removed = 0;    ///< deleted by the finish: no arrangement met the bound there (and any flagged outside)
  size_t finish_forced = 0;     ///< of those: one of each pair still over the bound when the finish's rounds ran out
  size_t finish_rounds = 0;     ///< the finish's relaxations
  size_t finish_near_rounds = 0;  ///< of those, of the spheres near the last jams only (the rest held)
  /// The most spheres one process looked at in a finish round (its own and
  /// a halo; one process: all; issue 31: fewer on LAMMPS at P > 1).
  size_t finish_largest_view = 0;
  size_t holes_filled = 0;      ///< spheres the finish inserted into holes (some may have gone again)
  ContainmentRepair containment;
  std::vector<PassStats> passes;
  std::vector<BirthSite> sites;
  /// Meshes of several parts: the closed parts of the inside the field
  /// resolves, and how many of them are too small for a sphere (left empty).
  size_t parts = 0, parts_too_small = 0;
  double field_seconds = 0;
  size_t field_bytes = 0;
  double field_spacing = 0;
  std::string device;
  double seconds = 0;
  /// Of `seconds`: before pass 1 less the field (the plan, the Embree
  /// scene, the sites, the device and its programs), and the exact check
  /// after the finish (containment, holes, metrics, colours).
  double setup_seconds = 0, verify_seconds = 0;
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

}  // namespace pfill
