/// @file params.hpp
/// @brief The settings of the particle engine as a user gives them
/// (EngineParams: the physics, the neighbour lists, the device tuning),
/// the constants derived from them (EngineConstants: sigma, cutoff, time
/// step, caps), shared by the OpenCL engine and the C++ reference so both
/// run the same physics, and the automatic choices made for a device
/// (resolve_for_device: the one place they are made).
#pragma once
#include <cstddef>
#include <string>

#include "pfill/vec3.hpp"

namespace pfill {

/// How the step's kernels are written: see EngineParams::step_form.
enum class StepForm { automatic, cpu, gpu };
/// Whether the `cpu` form lists each pair once: see EngineParams::newton.
enum class Newton { automatic, on, off };
/// Whether the `cpu` form queues the pairs in reach: see EngineParams::pair_queue.
enum class PairQueue { automatic, on, off };
/// Whether the `cpu` form prunes inner lists from the lists: see EngineParams::inner_lists.
enum class InnerLists { automatic, on, off };
/// Whether each pair's lengths scale with its radii: see EngineParams::pair_scaling.
enum class PairScaling { automatic, on, off };

struct DeviceInfo;

/// FIRE, the minimiser (Bitzek et al., PRL 97, 170201, 2006; kernels/physics.cl
/// pf_fire_next): each step the particles move by semi-implicit Euler with
/// the state's step, their velocities turned towards their forces by the
/// share alpha; dt grows while the power P = sum F.v stays positive and
/// every velocity is dropped when it is not. The OpenCL engine, the
/// reference and the LAMMPS engine (src/lammps/fire_minimiser.hpp, P
/// summed over the ranks each step) run it.
struct FireParams {
  bool on = false;            ///< FIRE instead of leapfrog with damping (then no damping: `damping` must be 0)
  double dt_max = 4;          ///< largest step, in units of PhysicsParams::dt (the first step)
  double dt_min = 0.02;       ///< smallest step, in the same units
  double grow = 1.1;          ///< dt grows by this a step after `delay` steps in a row with P > 0
  double shrink = 0.5;        ///< and shrinks by this at P <= 0
  double alpha_start = 0.1;   ///< the mixing share at the start and after a restart
  double alpha_shrink = 0.99; ///< alpha shrinks by this as dt grows
  int delay = 5;              ///< steps with P > 0 before dt grows
};

/// The physics. Lengths are in mesh units; a particle of radius `radius`
/// has mass 1 (mass scales with volume, (r / radius)^3).
struct PhysicsParams {
  /// Reference particle radius (> 0): mass 1, and the pair of two such
  /// spheres has the potential's sigma, cutoff and rest distance below; a
  /// pair of radii r_i, r_j has them scaled by (r_i + r_j) / (2 radius)
  /// (when max_radius exceeds it: polydisperse). The time step and the list
  /// capacities are set for this radius: with unequal spheres make it the
  /// smallest.
  double radius = 0.5;
  /// Largest radius a particle may have; 0: `radius`. With pair_scaling
  /// the cells and lists reach the largest pair's scaled cutoff.
  double max_radius = 0;
  /// Unequal spheres: `on` scales each pair's sigma, cutoff, rest distance
  /// and dashpot by q = (r_i + r_j) / (2 radius) (physics.cl
  /// PF_DEFINE_PAIR_SCALE2: exactly 1 for two spheres of `radius`), so
  /// every pair has the same potential in its own units and the same
  /// restitution; `off` runs every pair at q = 1 (one sigma; contacts still
  /// at r_i + r_j), as equal spheres always did. `automatic`: on when
  /// max_radius exceeds radius by more than kEqualRadiusTolerance (the
  /// fill's equal spheres pass a max_radius a little above their radius).
  PairScaling pair_scaling = PairScaling::automatic;
  double rest_distance = 0;        ///< centre distance at the potential's minimum; 0: 2 * radius (touching)
  double eps = 1;                  ///< depth of the potential well (> 0)
  double exponent_a = 12;          ///< repulsive exponent a (> b)
  double exponent_b = 6;           ///< attractive exponent b (> 0)
  double cutoff_sigma = 0;         ///< cutoff in units of sigma (e.g. 2.5); 0: purely repulsive (cutoff at the minimum)
  double restitution = 0.5;        ///< particle-particle restitution in [0, 1] (of the linearised contact; 1: none lost)
  double wall_restitution = 0.5;   ///< particle-wall restitution in [0, 1]
  /// The wall moved in by this (mesh units): added to every value of the
  /// field (as a float) as the kernels read it, so that a moved wall needs
  /// no second copy of the field (the finish's: up to 256 MiB).
  double wall_offset = 0;
  double damping = 0;              ///< velocity damping rate (1/time): u *= exp(-damping dt) a step
  double dt = 0;                   ///< time step; 0: 0.005 tau, tau = sigma sqrt(m / eps)
  double max_step_fraction = 0.05; ///< no particle moves more than this many sigma in one step
  double force_cap = 0;            ///< largest pair force; 0: the force that gives a unit mass the top speed in one step
  /// FIRE instead of leapfrog (FireParams). dt is then its first step; the
  /// speed cap keeps every step's move at max_step_fraction sigma.
  FireParams fire;
};

/// The neighbour lists and grid (results do not depend on them, beyond
/// rounding in the order forces are summed).
struct ListParams {
  /// Neighbour-list skin in units of sigma (lists rebuilt after moves of
  /// half of it). 0: automatic, 0.5 in the `cpu` step form (its inner lists
  /// keep the pair loop short, so longer lists pay in rarer rebuilds: 3-4%
  /// a step at N = 1e5, both cutoffs; bench_variants) and 0.3 in the `gpu`
  /// form (which reads the whole list every step).
  double skin_sigma = 0;
  /// Particles are born at speed (a fill's passes 1 and 2 and its settle):
  /// some particle always moves at the top speed, so lists go stale every
  /// few steps, and the `cpu` form's automatic skin for purely repulsive
  /// spheres is kCpuFormBirthsSkinSigma. Off for relaxations.
  bool births_at_speed = false;
  Box3 domain;                     ///< cell-grid box when no field is set (particles outside still work, slower)
  /// `cpu` form: dynamic pruning (as GROMACS does it). Every so often each
  /// list is pruned to an inner list of the pairs within the reach plus
  /// `inner_skin_sigma`, which the pair loop then reads; a particle that
  /// moved half of that since the last pruning makes the next step prune
  /// again (the lists themselves still rebuild after moves of half the
  /// skin). The pair loop then skips the ~40% of a list's entries that the
  /// skin adds at rc = 2.5 sigma, at the cost of a pruning pass every few
  /// steps and a second list buffer. Each inner list holds first the
  /// entries that may touch before the next pruning (touch distance plus
  /// the inner skin), and the pair loop runs the contact damping on those
  /// chunks only. 0.07 sigma ran 3-4% faster than 0.1 at rc = 2.5 (N = 1e5,
  /// bench_variants); the flat optimum lies between 0.05 and 0.1, and a
  /// larger `skin_sigma` (0.4-0.5) gains another 2-4% there (fewer
  /// rebuilds, longer lists). `automatic`: on with a cutoff
  /// (cutoff_sigma > 0), off for purely repulsive potentials, whose fast
  /// fills would prune nearly every step. `gpu` form: unused.
  InnerLists inner_lists = InnerLists::automatic;
  double inner_skin_sigma = 0.07;  ///< inner-list skin in sigma (< skin_sigma; see inner_lists)
};

/// How the step runs on the device. The `automatic` choices are made by
/// resolve_for_device.
struct DeviceTuning {
  size_t history_capacity = 4096;  ///< per-step records kept on the device between reads
  size_t work_group = 128;         ///< preferred work-group size (a power of two; the device may lower it)
  /// Wall field storage: false (default) a global buffer; true a CL_R/CL_FLOAT
  /// 3D image read by a NEAREST sampler at the 8 corners with the buffer
  /// path's trilinear formula (same value and gradient; hardware LINEAR
  /// filtering is not used: 8-bit weights on GPUs). A device without image
  /// support, or a field larger than its 3D image limits, is a pfill::Error
  /// (no silent fallback: the setting is explicit).
  bool field_image = false;
  /// How the step's kernels are written (kernels/cpu_*.cl, gpu_*.cl): `cpu` takes 8
  /// list entries at a time as float8 vectors (PoCL turns them into SIMD)
  /// in a kernel of its own (pair_forces) and sums the per-step scalars one
  /// work-item to a run (no barriers); `gpu` takes entries 4 at a time with
  /// one pair per work-item, interleaves the rows of 32 particles
  /// (coalesced), sums forces in fixed point and the scalars in
  /// work-groups. Same physics, same tests; `automatic` picks by the
  /// device's type.
  StepForm step_form = StepForm::automatic;
  /// `cpu` form: list each pair once and apply its force to both particles
  /// (Newton's third law: half the pair work). Each pair_forces work-item
  /// then sums into a force buffer of its own, which `advance` adds up for
  /// every particle: worth it on few cores, not on many. `automatic`: on
  /// with at most 4 compute units. `gpu` form: always off.
  Newton newton = Newton::automatic;
  /// With Newton on: how many work-items compute the pair forces, each over
  /// a block of particles and into a force buffer of its own (capacity x 16
  /// bytes). 0: one per compute unit, and fewer where the buffers would
  /// pass 512 MiB. Results depend on it (summation order).
  size_t force_buffers = 0;
  /// `cpu` form: test each row's entries first and queue those within
  /// reach, then compute the queued pairs 8 at a time whatever rows they
  /// came from (both particles' forces scattered), instead of running a
  /// whole 8-lane force batch for every 8 entries of a row. Pays where rows
  /// are short and few entries are in reach (purely repulsive lists);
  /// `automatic`: on for purely repulsive potentials. `gpu` form: unused.
  PairQueue pair_queue = PairQueue::automatic;
};

/// What the user sets: the three groups side by side (their fields are
/// the engine's settings, e.g. `p.radius`, `p.skin_sigma`, `p.work_group`).
struct EngineParams : PhysicsParams, ListParams, DeviceTuning {};

/// EngineParams' automatic choices made for one device (resolve_for_device).
struct DeviceChoices {
  bool gpu_form = false;    ///< step_form: the `gpu` form's kernels (else the `cpu` form's)
  bool newton = false;      ///< newton (cpu form only)
  bool pair_queue = false;  ///< pair_queue (cpu form only)
  bool inner_lists = false; ///< inner_lists (cpu form only)
  double skin_sigma = 0;    ///< skin_sigma; when automatic, the form's (kCpuFormSkinSigma, kGpuFormSkinSigma)
  size_t work_group = 1;    ///< the group of `advance` and the per-step sums: work_group lowered to the device's limit, a power of two
  /// One line saying what was chosen, e.g. "engine on CPU 'cpu-x' (2
  /// compute units): cpu step form, skin 0.5 sigma (automatic), newton on
  /// (automatic), ...".
  std::string describe() const;
  std::string device_line;  ///< the device, as describe() names it
  bool skin_automatic = false, form_automatic = false, newton_automatic = false, queue_automatic = false,
       inner_automatic = false;
};

/// The one place the automatic settings are resolved: for `device`'s type,
/// compute units and work-group limit, and `p`'s potential (cutoff).
DeviceChoices resolve_for_device(const DeviceInfo& device, const EngineParams& p);

/// Everything derived from EngineParams (see derive_constants).
struct EngineConstants {
  double sigma = 0;          ///< rest_distance / (a/b)^(1/(a-b))
  double cutoff = 0;         ///< rc in mesh units
  double tau = 0;            ///< sigma sqrt(1 / eps): the potential's time scale for unit mass
  double dt = 0;             ///< the time step
  double max_speed = 0;      ///< max_step_fraction * sigma / dt: speeds are clamped to it
  double force_cap = 0;      ///< largest pair force
  double damping_factor = 1; ///< exp(-damping dt)
  double contact_distance = 0; ///< the rest distance: contacts damp while d < max(r_i + r_j, this)
  double dashpot = 0;        ///< 2 zeta sqrt(k): contact damping (physics.cl pf_contact_damping)
  double cell_size = 0;      ///< cell edge of level 0: the reach of its largest pair plus the skin
  /// Unequal spheres of radii up to 1:2^k or more: the cells come in
  /// levels (Ogarko and Luding 2012), level L for the spheres of radius
  /// above level_radius 2^(L-1) and up to level_radius 2^L (level 0 from
  /// the smallest, the top to max_radius), its cells 2^L cell_size wide
  /// (nested: the largest pair of a level reaches one cell of it).
  /// 1 otherwise: one grid, as equal spheres.
  unsigned cell_levels = 1;
  double level_radius = 0;   ///< the largest radius of level 0 (max_radius with one level)
  double max_radius = 0;
  /// EngineParams::pair_scaling resolved: each pair's sigma, cutoff, rest
  /// distance and dashpot scale with (r_i + r_j) / (2 radius) (physics.cl
  /// PF_DEFINE_PAIR_SCALE2); otherwise every pair runs at scale 1 (equal
  /// spheres, as before).
  bool polydisperse = false;
  unsigned cell_capacity = 0;  ///< particles a cell of level 0 can list (more are dropped and counted as overflow)
  unsigned cell_capacity_up = 0;  ///< particles a cell of a level above 0 can list (cell_capacity with one level)
  double skin = 0;             ///< neighbour-list skin
  double list_reach = 0;       ///< max(q cutoff, 2 max_radius, q rest distance) + skin, q = max_radius / radius when polydisperse, else 1
  unsigned list_capacity = 0;  ///< neighbours a list can hold (more are dropped and counted as overflow)
  double inner_skin = 0;       ///< inner-list skin (EngineParams::inner_lists)
  double inner_reach = 0;      ///< max(q cutoff, 2 max_radius, q rest distance) + inner_skin
  /// Words a particle of the inner lists' buffer (EngineParams::inner_lists):
  /// a block's inner rows are packed into this many a particle, a bound on
  /// the entries within the inner reach, as list_capacity is on the list's.
  unsigned inner_capacity = 0;
  int a_half = 0, b_half = 0;  ///< a/2, b/2 when even integers (fast powers), else 0
};

/// With PairScaling::automatic, max_radius up to radius (1 + this) is
/// equal spheres (EngineConstants::polydisperse): the finish passes radius
/// (1 + 1e-6) / (1 - max_overlap / 2), and a spread this small changes
/// the pairs' lengths by at most half of it.
constexpr double kEqualRadiusTolerance = 0.1;

/// Steps of the wall's push back inside along the field's gradient
/// (physics.cl pf_wall_push; PF_WALL_ITERATIONS in the kernels).
constexpr int kWallIterations = 2;

/// The automatic skins (EngineParams::skin_sigma = 0) of the two step forms.
constexpr double kCpuFormSkinSigma = 0.5;
constexpr double kGpuFormSkinSigma = 0.3;
/// The `cpu` form's automatic skin for purely repulsive unequal spheres
/// (the fill's default) whose largest radius is at least kMixSkinRatio
/// times the reference: the small, light spheres
/// drift further per step, so lists at 0.5 were rebuilt three times as
/// often (1:4 at 10,000: 3% of steps, at 3.2 ms each), while the skin's
/// share of the large pairs' reach falls with the ratio (bench_step
/// --radii-ratio 4 --cutoff repulsive: 1.34x equal spheres' cost per
/// particle-step at 0.5, 1.18x at 0.9). With a cutoff (--cutoff lj) the
/// rows are long and 0.9 cost more than it saved (1:2: 1.30x -> 1.50x).
constexpr double kCpuFormMixSkinSigma = 0.9;
/// The `cpu` form's automatic skin while particles are born at speed
/// (ListParams::births_at_speed), purely repulsive: at the top speed of 0.1
/// sigma a step a particle crosses half a 0.5 skin in 3 steps, and lists
/// were rebuilt on a third of pass 1's steps (spot -n 100000: 1,003 of
/// 3,024), each costing 4-5 plain steps. At 0.9, a fifth (627): pass 1's
/// kernels 17% less at 1e5 (fill --max-steps 3000, alternated) and 25% in
/// bench_step --fill. With a cutoff the rows are long (as for mixes).
constexpr double kCpuFormBirthsSkinSigma = 0.9;
constexpr double kMixSkinRatio = 2;
/// The automatic skin of a step form for `p`'s spheres (0.5 / 0.3, or
/// kCpuFormMixSkinSigma for the `cpu` form's wide mixes).
double automatic_skin_sigma(const EngineParams& p, bool gpu_form);

/// Checks `p` (throws pfill::Error naming the bad setting) and derives the constants.
EngineConstants derive_constants(const EngineParams& p);

/// Mass of a particle of radius r: (r / p.radius)^3.
double particle_mass(const EngineParams& p, double r);

}  // namespace pfill
