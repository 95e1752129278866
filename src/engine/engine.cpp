// The OpenCL particle engine: device buffers, program build, and the host
// side of births, removals, steps and read-backs (see engine.hpp and the
// top of kernels/common.cl for the step's design).
#include "pfill/engine/engine.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <sstream>
#include <vector>

#include "pfill/device/device.hpp"
#include "pfill/device/program.hpp"
#include "engine/cell_grid.hpp"
#include "engine/device_field.hpp"
#include "engine/neighbour_lists.hpp"
#include "engine/step_history.hpp"
#include "pfill/error.hpp"

namespace pfill {

namespace {

std::string flt(double v) {
  std::ostringstream s;
  s.precision(9);
  s << std::scientific << v << "f";
  return s.str();
}

cl_float4 f4(double x, double y, double z, double w) {
  cl_float4 v;
  v.s[0] = static_cast<float>(x);
  v.s[1] = static_cast<float>(y);
  v.s[2] = static_cast<float>(z);
  v.s[3] = static_cast<float>(w);
  return v;
}

// The kernel files of a step form, in build order (kernels/common.cl
// says what each holds).
std::vector<std::string> kernel_files(bool gpu_form) {
  if (gpu_form)
    return {"physics.cl", "common.cl", "cells.cl", "gpu_lists.cl", "births_removals.cl", "field.cl", "gpu_step.cl"};
  return {"physics.cl", "common.cl",          "x86.cl",       "cells.cl",    "cpu_lists.cl",
          "births_removals.cl", "field.cl", "cpu_pairs.cl", "cpu_step.cl"};
}

// EngineParams::step_form resolved for the device.
bool uses_gpu_form(const Device& device, const EngineParams& p) {
  return p.step_form == StepForm::automatic ? device.info().type != "CPU" : p.step_form == StepForm::gpu;
}

// `p` with its automatic skin made the step form's.
EngineParams resolved_params(const Device& device, EngineParams p) {
  if (p.skin_sigma == 0) p.skin_sigma = uses_gpu_form(device, p) ? kGpuFormSkinSigma : kCpuFormSkinSigma;
  return p;
}

// derive_constants, plus (with field_image) the device's image support,
// checked before the program (which then declares an image3d_t) is built.
EngineConstants checked_constants(const Device& device, const EngineParams& p) {
  EngineConstants c = derive_constants(p);
  if (p.field_image && !device.device().getInfo<CL_DEVICE_IMAGE_SUPPORT>())
    throw Error("engine: device '" + device.info().name +
                "' has no image support (CL_DEVICE_IMAGE_SUPPORT); unset EngineParams::field_image");
  return c;
}

}  // namespace

struct Engine::Impl {
  Device& device;
  EngineParams params;
  EngineConstants constants;
  size_t group_size;  // PF_WG: the work-group of `advance` and `finalize_history` (before `program`)
  bool gpu_form;      // EngineParams::step_form resolved for this device (before `program`)
  bool newton;        // EngineParams::newton resolved (before `program`)
  bool pair_queue;    // EngineParams::pair_queue resolved (before `program`)
  bool inner;         // EngineParams::inner_lists resolved (before `program`)
  // Force buffers `advance` adds up: with Newton, one per pair_forces
  // work-item (EngineParams::force_buffers; set by reserve()); else 1 (0 on GPUs).
  size_t force_groups = 0;
  Program program;
  Kernel k_step, k_insert, k_birth, k_move, k_birth_linked, k_remove_linked, k_neighbours, k_pairs;
  NeighbourLists nl;  // the lists, their request words, the births linked in
  CellGrid cells;     // the grid the lists are built from (filled only on the steps that rebuild them)
  DeviceField wall;   // the distance field the wall kernels sample

  size_t n = 0, capacity = 0;
  std::vector<uint64_t> ids;  // Particle::id of each index, kept host-side through removals and sorts
  int cur = 0;  // which half of X and V holds the current state
  cl::Buffer X[2], V[2], flags, clearance;
  // CPU form: force_groups buffers of `capacity` forces (zero between
  // steps), and the list build's overflow bits for `advance`.
  cl::Buffer forces, build_bits;
  // CPU form with Newton: per force buffer, the particles [first, end)
  // whose forces pair_forces may have changed there (`advance` reads those)
  cl::Buffer force_spans;
  // Field.
  // The per-step records: the device's ring, the sums in flight, the read-back.
  std::unique_ptr<StepHistory> records;
  uint64_t steps = 0;
  std::vector<std::pair<std::string, cl::Event>> events;

  Impl(Device& d, const EngineParams& p)
      : device(d), params(resolved_params(d, p)), constants(checked_constants(d, params)), group_size(reduction_group(d, p)),
        gpu_form(uses_gpu_form(d, p)),
        newton(!gpu_form && (p.newton == Newton::automatic ? d.info().compute_units <= 4 : p.newton == Newton::on)),
        pair_queue(!gpu_form && (p.pair_queue == PairQueue::automatic ? p.cutoff_sigma <= 0 : p.pair_queue == PairQueue::on)),
        inner(!gpu_form && (p.inner_lists == InnerLists::automatic ? p.cutoff_sigma > 0 && p.inner_skin_sigma < params.skin_sigma
                                                                     : p.inner_lists == InnerLists::on)),
        program(d, kernel_files(gpu_form), defines()),
        nl(d, ListLayout{constants.list_capacity, newton, inner}),
        cells(d, constants.cell_size, constants.cell_capacity),
        wall(d, params.field_image) {
    k_step = program.kernel("advance", group_size);
    Kernel k_finalize = program.kernel("finalize_history", group_size);
    for (const Kernel* k : {&k_step, &k_finalize})
      if (k->work_group() != group_size)
        throw Error("engine: device '" + device.info().name + "' runs " + k->name() + " with at most " +
                    std::to_string(k->work_group()) + " work-items a group; set EngineParams::work_group to " +
                    std::to_string(k->work_group()));
    k_insert = program.kernel("insert_cells", params.work_group);
    k_birth = program.kernel("birth_one", 1);
    k_move = program.kernel("move_particle", 1);
    k_birth_linked = program.kernel("birth_linked", params.work_group);
    k_remove_linked = program.kernel("remove_linked", params.work_group);
    k_neighbours = program.kernel("list_neighbours", params.work_group);
    if (!gpu_form) k_pairs = program.kernel("pair_forces", 1);
    records = std::make_unique<StepHistory>(device, params.history_capacity, group_size, k_finalize,
                                            [this](Kernel& k, size_t items) { run(k, items); });
    reserve(64);
    if (!params.domain.empty()) set_domain(params.domain);
  }

  std::map<std::string, std::string> defines() const {
    const EngineConstants& c = constants;
    std::map<std::string, std::string> d = base_defines(c);
    if (params.field_image) d["PF_FIELD_IMAGE"] = "1";
    // (as a float: the sum a shifted copy of the field would hold)
    if (params.wall_offset != 0) d["PF_WALL_OFFSET"] = flt(static_cast<float>(params.wall_offset));
    size_t root = 1;  // about sqrt(PF_WG): two short serial runs
    while (4 * root * root <= group_size) root *= 2;
    d["PF_NEWTON"] = newton ? "1" : "0";
    d["PF_PAIR_QUEUE"] = pair_queue ? "1" : "0";
    d["PF_INNER"] = inner ? "1" : "0";
    d["PF_RI2"] = flt(c.inner_reach * c.inner_reach);
    d["PF_INNER_SKIN"] = flt(c.inner_skin);
    d["PF_CONTACT"] = flt(c.contact_distance);
    d["PF_HALF_INNER2"] = flt(0.25 * c.inner_skin * c.inner_skin);
    d["PF_FIX_SCALE"] = flt(std::ldexp(1.0, 47) / (c.force_cap * c.list_capacity));
    d["PF_FIX_MAX"] = flt(16384 * c.force_cap);
    d["PF_WG"] = std::to_string(group_size) + "u";
    d["PF_WG_ROOT"] = std::to_string(root) + "u";
    return d;
  }

  std::map<std::string, std::string> base_defines(const EngineConstants& c) const {
    return {{"PF_SIGMA2", flt(c.sigma * c.sigma)},
            {"PF_EPS", flt(params.eps)},
            {"PF_EXP_A", flt(params.exponent_a)},
            {"PF_EXP_B", flt(params.exponent_b)},
            {"PF_EXP_A_HALF", std::to_string(c.a_half)},
            {"PF_EXP_B_HALF", std::to_string(c.b_half)},
            {"PF_RC2", flt(c.cutoff * c.cutoff)},
            {"PF_FORCE_CAP", flt(c.force_cap)},
            {"PF_D_MIN", flt(1e-3 * c.sigma)},
            {"PF_DASHPOT", flt(c.dashpot)},
            {"PF_CONTACT2", flt(c.contact_distance * c.contact_distance)},
            {"PF_WALL_RESTITUTION", flt(params.wall_restitution)},
            {"PF_DT", flt(c.dt)},
            {"PF_DAMP", flt(c.damping_factor)},
            {"PF_VMAX", flt(c.max_speed)},
            {"PF_CELL_CAP", std::to_string(c.cell_capacity) + "u"},
            {"PF_WALL_ITERATIONS", "2"},
            {"PF_RL2", flt(c.list_reach * c.list_reach)},
            {"PF_HALF_SKIN2", flt(0.25 * c.skin * c.skin)},
            {"PF_LIST_CAP", std::to_string(c.list_capacity) + "u"}};
  }

  void run(Kernel& k, size_t items) {
    if (device.profiling()) {
      events.emplace_back(k.name(), cl::Event());
      launch(device, k, items, &events.back().second);
    } else {
      launch(device, k, items);
    }
  }

  // The work-group of `advance` and `finalize_history` (PF_WG, also the
  // chunk of the per-step sums): the preferred size, lowered to the
  // device's limit, a power of two.
  static size_t reduction_group(const Device& device, const EngineParams& p) {
    return floor_power_of_two(std::min(p.work_group, device.info().max_work_group));
  }

  // The force buffers for `cap` particles: with Newton
  // EngineParams::force_buffers, or one per compute unit within 512 MiB.
  size_t pair_force_groups(size_t cap) const {
    if (gpu_form) return 0;
    if (!newton) return 1;
    if (params.force_buffers > 0) return params.force_buffers;
    const size_t by_memory = (size_t(512) << 20) / (cap * sizeof(cl_float4));
    return std::clamp<size_t>(std::min<size_t>(device.info().compute_units, by_memory), 1, 16);
  }

  // pair_forces work-items: with Newton one per force buffer, else one per 64 particles.
  size_t pair_items() const { return newton ? force_groups : std::max<size_t>(1, (n + 63) / 64); }

  size_t groups_for(size_t count) const { return (count + group_size - 1) / group_size; }
  // Level-1 partials of a step of n particles: one a work-group (GPU
  // form), or one an octet of particles, the last maybe partial (cpu_step.cl
  // advance).
  size_t level1_count(size_t count) const {
    return std::max<size_t>(gpu_form ? groups_for(count) : (count + 7) / 8, 1);
  }

  // New buffers may reuse a freed buffer's handle: set every argument again.
  void forget_kernel_args() {
    for (Kernel* k : {&k_step, &k_insert, &k_birth, &k_move, &k_birth_linked, &k_remove_linked, &k_neighbours,
                      &k_pairs})
      k->forget_args();
  }

  // Room for `want` particles: doubling, state copied on the device.
  // The next capacity: doubling up to kDoubleUpTo particles, then a
  // quarter more (a multiple of 8: `advance` reads whole octets), so
  // that large fills do not hold up to twice the buffers they use (every
  // particle slot costs ~300 bytes on the device, the lists most).
  static constexpr size_t kDoubleUpTo = size_t(1) << 16;
  static size_t grown_capacity(size_t cap) { return cap < kDoubleUpTo ? 2 * cap : (cap + cap / 4 + 7) / 8 * 8; }

  void reserve(size_t want) {
    if (want <= capacity) return;
    size_t cap = std::max<size_t>(capacity, 64);
    while (cap < want) cap = grown_capacity(cap);
    // CPU list rows hold byte offsets (16 j: see PF_ENTRY in cpu_lists.cl),
    // which the AVX-512 gathers take as signed 32-bit.
    if (!gpu_form && cap > (size_t(1) << 27))
      throw Error("engine: " + std::to_string(want) + " particles are more than the CPU form holds (2^27); use a larger radius");
    records->finish_pending(steps);  // the record buffers are reallocated below
    cl::Buffer nx[2], nv[2];
    for (int h = 0; h < (gpu_form ? 2 : 1); ++h) {
      nx[h] = device.make_buffer(cap * sizeof(cl_float4), "positions");
      nv[h] = device.make_buffer(cap * sizeof(cl_float4), "velocities");
      // Zeroed: the CPU pair loop reads (then masks) particles a row only
      // held once, which must be finite (0 x NaN would not vanish).
      for (cl::Buffer* b : {&nx[h], &nv[h]})
        check_cl(device.queue().enqueueFillBuffer(*b, cl_float(0), 0, cap * sizeof(cl_float4)), "clEnqueueFillBuffer",
                 "positions and velocities");
    }
    cl::Buffer nf = device.make_buffer(cap * sizeof(cl_uint), "flags");
    cl::Buffer nc = device.make_buffer(cap * sizeof(cl_float), "wall clearance");
    if (n > 0) {
      auto& q = device.queue();
      check_cl(q.enqueueCopyBuffer(X[cur], nx[cur], 0, 0, n * sizeof(cl_float4)), "clEnqueueCopyBuffer", "positions");
      check_cl(q.enqueueCopyBuffer(V[cur], nv[cur], 0, 0, n * sizeof(cl_float4)), "clEnqueueCopyBuffer", "velocities");
      check_cl(q.enqueueCopyBuffer(flags, nf, 0, 0, n * sizeof(cl_uint)), "clEnqueueCopyBuffer", "flags");
      check_cl(q.enqueueCopyBuffer(clearance, nc, 0, 0, n * sizeof(cl_float)), "clEnqueueCopyBuffer", "clearance");
    }
    for (int h = 0; h < 2; ++h) {
      X[h] = nx[h];
      V[h] = nv[h];
    }
    flags = nf;
    clearance = nc;
    capacity = cap;
    force_groups = pair_force_groups(cap);
    nl.reserve(cap, force_groups);
    const size_t force_count = std::max<size_t>(force_groups * cap, 1);
    forces = device.make_buffer(force_count * sizeof(cl_float4), "pair forces");
    check_cl(device.queue().enqueueFillBuffer(forces, cl_float(0), 0, force_count * sizeof(cl_float4)),
             "clEnqueueFillBuffer", "pair forces");
    build_bits = device.make_buffer((gpu_form ? 1 : cap) * sizeof(cl_uint), "list build bits");
    const size_t span_bytes = std::max<size_t>(force_groups, 1) * sizeof(cl_uint2);
    force_spans = device.make_buffer(span_bytes, "pair force spans");
    check_cl(device.queue().enqueueFillBuffer(force_spans, cl_uint(0), 0, span_bytes), "clEnqueueFillBuffer",
             "pair force spans");
    cells.reserve(cap);
    forget_kernel_args();
    records->reserve(level1_count(cap), steps);
  }

  void set_field(const ScalarGrid& field, bool borrow);

  // The neighbour grid over `box` (the lists are then rebuilt).
  void set_domain(const Box3& box) {
    cells.set_domain(box);
    nl.valid = false;
    forget_kernel_args();
  }

  // Lists X[cur] in this step's cells when `force` or when the list
  // rebuild request of the last step is raised (decided on the device).
  void insert_cells(bool force) {
    k_insert.set_args(X[cur], cells.counts, cells.slots, cells.base(steps), cells.total(), cells.touched,
                      cells.touched_upto, cl_uint(capacity), cells.origin, cells.inv, cells.dims, cl_uint(n),
                      nl.requests, NeighbourLists::read_slot(steps), cl_uint(force ? 1 : 0));
    // GPUs: an item a particle; CPU devices: a group a core, each item
    // looping (a launch of n items costs PoCL ~0.2 us a group even on the
    // steps that return at once).
    run(k_insert, gpu_form ? n : std::min(n, std::max<size_t>(1, device.info().compute_units) * params.work_group));
  }

  // One step: the cells (only when lists will be rebuilt), on CPU devices
  // the pair forces, then the update.
  void step() {
    cells.require_domain();
    if (records->full(steps)) records->drain(steps);
    // GPUs: ping-pong (advance reads other particles' X and V); CPU devices
    // update in place (advance reads only its own particle's), which spares
    // the cache the second copy and the writes their line reads.
    const int nxt = gpu_form ? 1 - cur : cur;
    const bool force = !nl.valid;
    insert_cells(force);
    if (!gpu_form) {
      k_pairs.set_args(X[cur], V[cur], cells.counts, cells.slots, cells.base(steps), cells.origin, cells.inv,
                       cells.dims, cl_uint(n), nl.rows, nl.counts, nl.origins, build_bits, nl.requests,
                       NeighbourLists::read_slot(steps), cl_uint(force ? 1 : 0), forces, cl_uint(capacity),
                       nl.sort_rows(), nl.inner_rows, nl.inner_counts, nl.prune_origins, nl.spans, force_spans);
      run(k_pairs, pair_items());
    }
    StepHistory& r = *records;
    // (the two forms' `advance` take different arguments: gpu_step.cl, cpu_step.cl)
    auto set_step_args = [&](const auto& field) {
      if (gpu_form)
        k_step.set_args(X[cur], V[cur], X[nxt], V[nxt], cells.counts, cells.slots, cells.base(steps),
                        cells.origin, cells.inv, cells.dims, field, wall.origin, wall.dims, flags, clearance,
                        cl_uint(n), r.level1_out(steps), r.level1_prev(steps), r.level1_pending(),
                        r.level2_out(steps), r.level2_prev(steps), r.level2_pending(), r.ring(),
                        r.slot_two_back(steps), nl.rows, nl.counts, nl.origins, nl.requests,
                        NeighbourLists::read_slot(steps), NeighbourLists::raise_slot(steps),
                        NeighbourLists::clear_slot(steps), cl_uint(force ? 1 : 0));
      else
        k_step.set_args(X[cur], V[cur], field, wall.origin, wall.dims, flags, clearance, cl_uint(n),
                        r.level1_out(steps), r.level1_prev(steps), r.level1_pending(), r.level2_out(steps),
                        r.level2_prev(steps), r.level2_pending(), r.ring(), r.slot_two_back(steps), nl.origins,
                        nl.prune_origins, nl.requests, NeighbourLists::read_slot(steps),
                        NeighbourLists::raise_slot(steps), NeighbourLists::clear_slot(steps), cl_uint(force ? 1 : 0),
                        forces, cl_uint(force_groups), cl_uint(capacity), force_spans, build_bits);
    };
    if (wall.as_image())
      set_step_args(wall.image());
    else
      set_step_args(wall.buffer());
    // an item a particle (GPU form) or an octet (CPU form: level1_count),
    // and a group for each level-2 partial
    run(k_step, std::max<size_t>({gpu_form ? n : level1_count(n), r.level2_now() * group_size, 1}));
    nl.newcomers.clear();
    r.stepped(level1_count(n));
    nl.valid = true;
    cur = nxt;
    ++steps;
  }
};

Engine::Engine(Device& device, const EngineParams& params) : impl_(std::make_unique<Impl>(device, params)) {}
Engine::~Engine() = default;

const EngineParams& Engine::params() const { return impl_->params; }
const EngineConstants& Engine::constants() const { return impl_->constants; }
size_t Engine::size() const { return impl_->n; }
uint64_t Engine::steps_done() const { return impl_->steps; }

void Engine::set_field(const ScalarGrid& field) { impl_->set_field(field, false); }

void Engine::share_field(const ScalarGrid& field) { impl_->set_field(field, true); }

void Engine::Impl::set_field(const ScalarGrid& field, bool borrow) {
  Impl& m = *this;
  m.wall.set(field, borrow);
  Box3 box;
  box.add(field.origin);
  box.add(field.upper());
  m.set_domain(box);
}

size_t Engine::add_particles(const std::vector<Particle>& particles) {
  Impl& m = *impl_;
  const size_t first = m.n;
  if (particles.empty()) return first;
  std::vector<cl_float4> xs, vs;
  for (const Particle& p : particles) {
    if (!(p.radius > 0 && p.radius <= m.constants.max_radius * (1 + 1e-9)))
      throw Error("engine: particle radius " + std::to_string(p.radius) + " is outside (0, max_radius = " +
                  std::to_string(m.constants.max_radius) + "]; raise EngineParams::max_radius");
    if (!is_finite(p.position) || !is_finite(p.velocity) || p.mass < 0 || !std::isfinite(p.mass))
      throw Error("engine: a particle to add has a non-finite position or velocity, or a bad mass");
    const double mass = p.mass > 0 ? p.mass : particle_mass(m.params, p.radius);
    xs.push_back(f4(p.position.x, p.position.y, p.position.z, p.radius));
    vs.push_back(f4(p.velocity.x, p.velocity.y, p.velocity.z, 1 / mass));
  }
  m.reserve(first + particles.size());
  for (const Particle& p : particles) m.ids.push_back(p.id);
  if (particles.size() == 1 && m.nl.valid && m.nl.newcomers.size() < 4) {  // link it into the lists in place
    m.k_birth_linked.set_args(m.X[m.cur], m.V[m.cur], m.flags, m.clearance, m.nl.rows, m.nl.counts, m.nl.spans,
                              m.nl.origins, m.nl.requests, NeighbourLists::read_slot(m.steps), cl_uint(first), xs[0],
                              vs[0]);
    m.run(m.k_birth_linked, first + 1);
    m.nl.newcomers.push_back(static_cast<int>(first));
    m.n += 1;
    return first;
  }
  m.nl.valid = false;  // the next step lists the newcomers
  if (particles.size() == 1) {
    m.k_birth.set_args(m.X[m.cur], m.V[m.cur], m.flags, m.clearance, cl_uint(first), xs[0], vs[0]);
    m.run(m.k_birth, 1);
    m.n += 1;
    return first;
  }
  auto& q = m.device.queue();
  const std::vector<cl_uint> zeros(particles.size(), 0);
  check_cl(q.enqueueWriteBuffer(m.X[m.cur], CL_TRUE, first * sizeof(cl_float4), xs.size() * sizeof(cl_float4),
                                xs.data()), "clEnqueueWriteBuffer", "positions");
  check_cl(q.enqueueWriteBuffer(m.V[m.cur], CL_TRUE, first * sizeof(cl_float4), vs.size() * sizeof(cl_float4),
                                vs.data()), "clEnqueueWriteBuffer", "velocities");
  check_cl(q.enqueueWriteBuffer(m.flags, CL_TRUE, first * sizeof(cl_uint), zeros.size() * sizeof(cl_uint),
                                zeros.data()), "clEnqueueWriteBuffer", "flags");
  check_cl(q.enqueueWriteBuffer(m.clearance, CL_TRUE, first * sizeof(cl_float), zeros.size() * sizeof(cl_float),
                                zeros.data()), "clEnqueueWriteBuffer", "clearance");  // 0.0f has the bits of 0u
  m.n += particles.size();
  return first;
}

void Engine::remove_particles(std::vector<size_t> indices) {
  Impl& m = *impl_;
  std::sort(indices.begin(), indices.end(), std::greater<size_t>());
  indices.erase(std::unique(indices.begin(), indices.end()), indices.end());
  for (size_t idx : indices)
    if (idx >= m.n)
      throw Error("engine: cannot remove particle " + std::to_string(idx) + " of " + std::to_string(m.n));
  for (size_t idx : indices) {
    const size_t last = m.n - 1;
    if (m.nl.valid) {  // keep the lists: drop `idx`, rename `last`
      m.k_remove_linked.set_args(m.X[m.cur], m.V[m.cur], m.flags, m.clearance, m.nl.rows, m.nl.counts,
                                 m.nl.spans, m.nl.origins, cl_uint(m.n), cl_uint(idx), m.nl.requests,
                                 NeighbourLists::read_slot(m.steps));
      m.run(m.k_remove_linked, m.n);
      // A newcomer's unsorted row moves with it from `last` to `idx`.
      for (int& k : m.nl.newcomers)
        if (k == static_cast<int>(idx)) k = -1;
      for (int& k : m.nl.newcomers)
        if (k == static_cast<int>(last)) k = static_cast<int>(idx);
    } else if (idx != last) {
      m.k_move.set_args(m.X[m.cur], m.V[m.cur], m.flags, m.clearance, cl_uint(last), cl_uint(idx));
      m.run(m.k_move, 1);
    }
    m.ids[idx] = m.ids[last];  // the ids follow the swap with the last
    m.ids.pop_back();
    // Counts past the last particle stay 0 (a linked birth counts up from there).
    m.nl.clear_count(last);
    m.n -= 1;
  }
}

size_t Engine::index_after_removal(size_t index, std::vector<size_t> removed, size_t count) {
  std::sort(removed.begin(), removed.end(), std::greater<size_t>());
  removed.erase(std::unique(removed.begin(), removed.end()), removed.end());
  for (size_t idx : removed) {  // as remove_particles: largest first, each swapped with the last
    const size_t last = --count;
    if (index == idx)
      index = kGone;
    else if (index == last)
      index = idx;
  }
  return index;
}

void Engine::run_steps(size_t k) {
  Impl& m = *impl_;
  for (size_t s = 0; s < k; ++s) m.step();
}

std::vector<StepRecord> Engine::read_history() {
  impl_->records->drain(impl_->steps);
  return impl_->records->take();
}

std::vector<Particle> Engine::read_particles() {
  Impl& m = *impl_;
  std::vector<cl_float4> xs(m.n), vs(m.n);
  if (m.n > 0) {
    check_cl(m.device.queue().enqueueReadBuffer(m.X[m.cur], CL_TRUE, 0, m.n * sizeof(cl_float4), xs.data()),
             "clEnqueueReadBuffer", "positions");
    check_cl(m.device.queue().enqueueReadBuffer(m.V[m.cur], CL_TRUE, 0, m.n * sizeof(cl_float4), vs.data()),
             "clEnqueueReadBuffer", "velocities");
  }
  std::vector<Particle> out(m.n);
  for (size_t i = 0; i < m.n; ++i) {
    out[i].position = {xs[i].s[0], xs[i].s[1], xs[i].s[2]};
    out[i].radius = xs[i].s[3];
    out[i].velocity = {vs[i].s[0], vs[i].s[1], vs[i].s[2]};
    out[i].mass = 1.0 / vs[i].s[3];
    out[i].id = m.ids[i];
  }
  return out;
}

namespace {

// The bits of v (21 of them) spread to every third bit.
uint64_t spread_bits(uint64_t v) {
  v &= 0x1FFFFF;
  v = (v | v << 32) & 0x1F00000000FFFFull;
  v = (v | v << 16) & 0x1F0000FF0000FFull;
  v = (v | v << 8) & 0x100F00F00F00F00Full;
  v = (v | v << 4) & 0x10C30C30C30C30C3ull;
  v = (v | v << 2) & 0x1249249249249249ull;
  return v;
}

}  // namespace

std::vector<size_t> Engine::sort_by_cells() {
  Impl& m = *impl_;
  m.cells.require_domain();
  m.records->finish_pending(m.steps);
  const size_t n = m.n;
  std::vector<cl_float4> xs(n), vs(n);
  std::vector<cl_uint> flags(n);
  auto& q = m.device.queue();
  if (n > 0) {
    check_cl(q.enqueueReadBuffer(m.X[m.cur], CL_FALSE, 0, n * sizeof(cl_float4), xs.data()), "clEnqueueReadBuffer",
             "positions");
    check_cl(q.enqueueReadBuffer(m.V[m.cur], CL_FALSE, 0, n * sizeof(cl_float4), vs.data()), "clEnqueueReadBuffer",
             "velocities");
    check_cl(q.enqueueReadBuffer(m.flags, CL_TRUE, 0, n * sizeof(cl_uint), flags.data()), "clEnqueueReadBuffer",
             "flags");
  }
  // Morton key of each particle's cell (clamped into the grid, as the kernels do).
  std::vector<std::pair<uint64_t, size_t>> keyed(n);
  for (size_t i = 0; i < n; ++i) {
    uint64_t key = 0;
    for (int a = 0; a < 3; ++a) {
      const double t = std::floor((xs[i].s[a] - m.cells.origin.s[a]) * m.cells.inv.s[a]);
      const int c = static_cast<int>(std::clamp(t, 0.0, static_cast<double>(m.cells.dims.s[a] - 1)));
      key |= spread_bits(static_cast<uint64_t>(c)) << a;
    }
    keyed[i] = {key, i};
  }
  std::sort(keyed.begin(), keyed.end());  // (key, old index): ties keep their order
  std::vector<size_t> order(n);
  std::vector<cl_float4> xs2(n), vs2(n);
  std::vector<cl_uint> flags2(n);
  std::vector<uint64_t> ids2(n);
  for (size_t k = 0; k < n; ++k) {
    const size_t i = keyed[k].second;
    order[k] = i;
    ids2[k] = m.ids[i];
    xs2[k] = xs[i];
    vs2[k] = vs[i];
    flags2[k] = flags[i];
  }
  if (n > 0) {
    check_cl(q.enqueueWriteBuffer(m.X[m.cur], CL_FALSE, 0, n * sizeof(cl_float4), xs2.data()),
             "clEnqueueWriteBuffer", "positions");
    check_cl(q.enqueueWriteBuffer(m.V[m.cur], CL_FALSE, 0, n * sizeof(cl_float4), vs2.data()),
             "clEnqueueWriteBuffer", "velocities");
    check_cl(q.enqueueWriteBuffer(m.flags, CL_TRUE, 0, n * sizeof(cl_uint), flags2.data()), "clEnqueueWriteBuffer",
             "flags");
    // Wall clearances are lower bounds, a cache: 0 makes the next step sample the field.
    check_cl(q.enqueueFillBuffer(m.clearance, cl_float(0), 0, n * sizeof(cl_float)), "clEnqueueFillBuffer",
             "clearance");
  }
  m.ids = std::move(ids2);
  m.nl.valid = false;  // the next step rebuilds every list
  m.nl.newcomers.clear();
  return order;
}

std::vector<size_t> Engine::flagged_particles() {
  Impl& m = *impl_;
  std::vector<cl_uint> f(m.n);
  if (m.n > 0)
    check_cl(m.device.queue().enqueueReadBuffer(m.flags, CL_TRUE, 0, m.n * sizeof(cl_uint), f.data()),
             "clEnqueueReadBuffer", "flags");
  std::vector<size_t> out;
  for (size_t i = 0; i < m.n; ++i)
    if (f[i]) out.push_back(i);
  return out;
}

void Engine::clear_flags() {
  Impl& m = *impl_;
  check_cl(m.device.queue().enqueueFillBuffer(m.flags, cl_uint(0), 0, m.capacity * sizeof(cl_uint)),
           "clEnqueueFillBuffer", "flags");
}

void Engine::finish() { impl_->device.finish(); }

std::vector<std::vector<uint32_t>> Engine::neighbour_lists() {
  Impl& m = *impl_;
  m.cells.require_domain();
  m.insert_cells(true);
  const cl_uint max_out = 256;
  cl::Buffer counts = m.device.make_buffer(std::max<size_t>(m.n, 1) * sizeof(cl_uint), "neighbour counts");
  cl::Buffer lists = m.device.make_buffer(std::max<size_t>(m.n, 1) * max_out * sizeof(cl_uint), "neighbour lists");
  m.k_neighbours.set_args(m.X[m.cur], m.cells.counts, m.cells.slots, m.cells.base(m.steps), m.cells.origin,
                          m.cells.inv, m.cells.dims, cl_uint(m.n), counts, lists, max_out);
  m.run(m.k_neighbours, m.n);
  m.cells.clear();  // as the steps expect them: this step's set empty
  std::vector<cl_uint> c(m.n), l(m.n * max_out);
  if (m.n > 0) {
    check_cl(m.device.queue().enqueueReadBuffer(counts, CL_TRUE, 0, c.size() * sizeof(cl_uint), c.data()),
             "clEnqueueReadBuffer", "neighbour counts");
    check_cl(m.device.queue().enqueueReadBuffer(lists, CL_TRUE, 0, l.size() * sizeof(cl_uint), l.data()),
             "clEnqueueReadBuffer", "neighbour lists");
  }
  std::vector<std::vector<uint32_t>> out(m.n);
  for (size_t i = 0; i < m.n; ++i) {
    if (c[i] > max_out) throw Error("engine: particle " + std::to_string(i) + " has more than 256 neighbours");
    out[i].assign(l.begin() + i * max_out, l.begin() + i * max_out + c[i]);
  }
  return out;
}

std::map<std::string, double> Engine::kernel_times() {
  Impl& m = *impl_;
  std::map<std::string, double> out;
  if (!m.device.profiling()) return out;
  m.device.finish();
  for (auto& [name, ev] : m.events) {
    cl_ulong start = 0, end = 0;
    check_cl(ev.getProfilingInfo(CL_PROFILING_COMMAND_START, &start), "clGetEventProfilingInfo", name);
    check_cl(ev.getProfilingInfo(CL_PROFILING_COMMAND_END, &end), "clGetEventProfilingInfo", name);
    out[name] += static_cast<double>(end - start) * 1e-9;
  }
  m.events.clear();
  return out;
}

}  // namespace pfill
