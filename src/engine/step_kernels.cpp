// The kernels both step forms share, bound by name to the engine's parts
// (see step_kernels.hpp), and the program's defines.
#include "engine/step_kernels.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "pfill/error.hpp"

namespace pfill {

namespace {

std::string flt(double v) {
  std::ostringstream s;
  s.precision(9);
  s << std::scientific << v << "f";
  return s.str();
}

// EngineConstants with, for EngineParams::field_image, the device's
// image support checked before a program declaring an image3d_t is built.
EngineConstants checked_constants(const Device& device, const EngineParams& p) {
  EngineConstants c = derive_constants(p);
  if (p.field_image && !device.device().getInfo<CL_DEVICE_IMAGE_SUPPORT>())
    throw Error("engine: device '" + device.info().name +
                "' has no image support (CL_DEVICE_IMAGE_SUPPORT); unset EngineParams::field_image");
  return c;
}

EngineParams with_skin(EngineParams p, const DeviceChoices& c) {
  p.skin_sigma = c.skin_sigma;
  return p;
}

}  // namespace

EngineState::EngineState(Device& d, const EngineParams& p)
    : device(d),
      choices(resolve_for_device(d.info(), p)),
      params(with_skin(p, choices)),
      constants(checked_constants(d, params)),
      particles(d),
      lists(d, ListLayout{constants.list_capacity, constants.inner_capacity, choices.newton, choices.inner_lists,
                          choices.gpu_form}),
      cells(d, constants.cell_size, constants.cell_capacity, constants.cell_levels, constants.cell_capacity_up),
      wall(d, params.field_image),
      fire(d, "FIRE state") {
  fire.reset(2, true);
}

void EngineState::run(Kernel& k, size_t items) {
  if (device.profiling()) {
    events.emplace_back(k.name(), cl::Event());
    launch(device, k, items, &events.back().second);
  } else {
    launch(device, k, items);
  }
}

std::map<std::string, std::string> shared_defines(const EngineState& s) {
  const EngineConstants& c = s.constants;
  const EngineParams& p = s.params;
  size_t root = 1;  // about sqrt(PF_WG): two short serial runs
  while (4 * root * root <= s.choices.work_group) root *= 2;
  std::map<std::string, std::string> d = {
      {"PF_SIGMA2", flt(c.sigma * c.sigma)},
      {"PF_EPS", flt(p.eps)},
      {"PF_EXP_A", flt(p.exponent_a)},
      {"PF_EXP_B", flt(p.exponent_b)},
      {"PF_EXP_A_HALF", std::to_string(c.a_half)},
      {"PF_EXP_B_HALF", std::to_string(c.b_half)},
      {"PF_RC2", flt(c.cutoff * c.cutoff)},
      {"PF_FORCE_CAP", flt(c.force_cap)},
      {"PF_D_MIN", flt(1e-3 * c.sigma)},
      {"PF_DASHPOT", flt(c.dashpot)},
      {"PF_CONTACT2", flt(c.contact_distance * c.contact_distance)},
      {"PF_WALL_RESTITUTION", flt(p.wall_restitution)},
      {"PF_DT", flt(c.dt)},
      {"PF_DAMP", flt(c.damping_factor)},
      {"PF_VMAX", flt(c.max_speed)},
      {"PF_CELL_CAP", std::to_string(c.cell_capacity) + "u"},
      {"PF_CELL_CAP_UP", std::to_string(c.cell_capacity_up) + "u"},
      {"PF_LEVELS", std::to_string(c.cell_levels) + "u"},
      {"PF_LEVEL_R0", flt(c.level_radius * (1 + 1e-6))},  // (a sphere of exactly level_radius in level 0)
      {"PF_WALL_ITERATIONS", std::to_string(kWallIterations)},
      {"PF_RL2", flt(c.list_reach * c.list_reach)},
      {"PF_HALF_SKIN2", flt(0.25 * c.skin * c.skin)},
      {"PF_LIST_CAP", std::to_string(c.list_capacity) + "u"},
      {"PF_NEWTON", s.choices.newton ? "1" : "0"},
      {"PF_PAIR_QUEUE", s.choices.pair_queue ? "1" : "0"},
      {"PF_INNER", s.choices.inner_lists ? "1" : "0"},
      {"PF_INNER_CAP", std::to_string(c.inner_capacity) + "u"},
      {"PF_RI2", flt(c.inner_reach * c.inner_reach)},
      {"PF_INNER_SKIN", flt(c.inner_skin)},
      {"PF_CONTACT", flt(c.contact_distance)},
      {"PF_HALF_INNER2", flt(0.25 * c.inner_skin * c.inner_skin)},
      {"PF_POLY", c.polydisperse ? "1" : "0"},
      // the reference pair's r_i + r_j as the kernels add two float radii, and 1 / its square
      {"PF_RS_REF", flt(2 * static_cast<double>(static_cast<float>(p.radius)))},
      {"PF_INV_RS_REF2", flt(1 / (4.0 * p.radius * p.radius))},
      {"PF_INV_RS_REF", flt(1 / (2.0 * p.radius))},
      {"PF_REACH_REF", flt(std::max(c.cutoff, c.contact_distance))},
      {"PF_SKIN", flt(c.skin)},
      {"PF_FIX_SCALE", flt(std::ldexp(1.0, 47) / (c.force_cap * c.list_capacity))},
      {"PF_FIX_MAX", flt(16384 * c.force_cap)},
      {"PF_WG", std::to_string(s.choices.work_group) + "u"},
      {"PF_WG_ROOT", std::to_string(root) + "u"}};
  if (p.fire.on) {
    const FireParams& f = p.fire;
    d["PF_FIRE"] = "1";
    d["PF_STEP_CAP"] = flt(c.max_speed * c.dt);  // a step's largest move, whatever FIRE's dt
    d["PF_FIRE_DT_MAX"] = flt(f.dt_max * c.dt);
    d["PF_FIRE_DT_MIN"] = flt(f.dt_min * c.dt);
    d["PF_FIRE_GROW"] = flt(f.grow);
    d["PF_FIRE_SHRINK"] = flt(f.shrink);
    d["PF_FIRE_ALPHA_START"] = flt(f.alpha_start);
    d["PF_FIRE_ALPHA_SHRINK"] = flt(f.alpha_shrink);
    d["PF_FIRE_DELAY"] = flt(f.delay);
  }
  if (p.field_image) d["PF_FIELD_IMAGE"] = "1";
  // (as a float: the sum a shifted copy of the field would hold)
  if (p.wall_offset != 0) d["PF_WALL_OFFSET"] = flt(static_cast<float>(p.wall_offset));
  return d;
}

StepKernels::StepKernels(EngineState& state, const std::vector<std::string>& files,
                         std::map<std::string, std::string> defines)
    : s(state), program(state.device, files, defines) {
  const size_t wg = s.choices.work_group;
  advance = program.kernel("advance", wg);
  Kernel finalize = program.kernel("finalize_history", wg);
  for (const Kernel* k : {&advance, &finalize})
    if (k->work_group() != wg)
      throw Error("engine: device '" + s.device.info().name + "' runs " + k->name() + " with at most " +
                  std::to_string(k->work_group()) + " work-items a group; set EngineParams::work_group to " +
                  std::to_string(k->work_group()));
  insert = program.kernel("insert_cells", s.params.work_group);
  birth_one = program.kernel("birth_one", 1);
  move_particle = program.kernel("move_particle", 1);
  link_birth = program.kernel("birth_linked", s.params.work_group);
  unlink_removal = program.kernel("remove_linked", s.params.work_group);
  list_neighbours = program.kernel("list_neighbours", s.params.work_group);
  EngineState* st = &s;
  s.records = std::make_unique<StepHistory>(s.device, s.params.history_capacity, wg, finalize,
                                            [st](Kernel& k, size_t items) { st->run(k, items); },
                                            s.fire.buffer(), s.params.fire.on);
}

std::vector<Kernel*> StepKernels::kernels() {
  return {&advance, &insert, &birth_one, &move_particle, &link_birth, &unlink_removal, &list_neighbours};
}

void StepKernels::bind_shared(Kernel& k, bool force_rebuild) {
  const uint64_t t = s.steps;
  const ParticleArrays& p = s.particles;
  const CellGrid& c = s.cells;
  const NeighbourLists& l = s.lists;
  StepHistory& r = *s.records;
  k.bind("X", p.x()).bind("V", p.v()).bind("flags", p.flags).bind("C", p.clearance).bind("n", cl_uint(s.n));
  k.bind("counts", c.counts).bind("slots", c.slots).bind("cell_base", c.base(t)).bind("cell_origin", c.origin);
  k.bind("cell_inv", c.inv).bind("cell_dims", c.dims).bind("level_mask", s.level_mask);
  k.bind("list", l.rows).bind("list_count", l.counts).bind("XREF", l.origins).bind("spans", l.spans);
  k.bind("inner_list", l.inner_rows).bind("inner_count", l.inner_counts).bind("XPRUNE", l.prune_origins);
  k.bind("sort_rows", l.sort_rows()).bind("request", l.requests);
  k.bind("request_read", NeighbourLists::read_slot(t)).bind("request_next", NeighbourLists::read_slot(t));
  k.bind("request_raise", NeighbourLists::raise_slot(t)).bind("request_clear", NeighbourLists::clear_slot(t));
  k.bind("force_rebuild", cl_uint(force_rebuild ? 1 : 0));
  if (s.wall.as_image())
    k.bind("sdf", s.wall.image());
  else
    k.bind("sdf", s.wall.buffer());
  k.bind("sdf_origin", s.wall.origin).bind("sdf_dims", s.wall.dims);
  k.bind("kept_cell", p.kept_cell).bind("kept_corners", p.kept_corners);
  k.bind("L1_out", r.level1_out(t)).bind("L1_prev", r.level1_prev(t)).bind("g1_prev", r.level1_pending());
  k.bind("L2_out", r.level2_out(t)).bind("L2_prev", r.level2_prev(t)).bind("g2_prev2", r.level2_pending());
  k.bind("history", r.ring()).bind("slot_prev2", r.slot_two_back(t));
  k.bind("fire", s.fire).bind("fire_read", cl_uint(t % 2)).bind("fire_write", cl_uint((t + 1) % 2));
  k.bind("step_index", cl_uint(t));
}

void StepKernels::step() {
  s.cells.require_domain();
  if (s.records->full(s.steps)) s.records->drain(s.steps);
  const bool force_rebuild = !s.lists.valid;
  insert_cells(force_rebuild);
  enqueue_step(force_rebuild);
  s.lists.newcomers.clear();
  s.records->stepped(level1_count(s.n));
  s.lists.valid = true;
  s.particles.swap();
  ++s.steps;
}

void StepKernels::insert_cells(bool force) {
  bind_shared(insert, false);
  insert.set("cells", s.cells.total()).set("touched", s.cells.touched).set("touched_upto", s.cells.touched_upto);
  insert.set("touched_stride", cl_uint(s.particles.capacity())).set("force", cl_uint(force ? 1 : 0));
  s.run(insert, insert_items());
}

// The next capacity: doubling up to kDoubleUpTo particles, then a quarter
// more (a multiple of 8: `advance` reads whole octets), so that large fills
// do not hold up to twice the buffers they use (every particle slot costs
// ~300 bytes on the device, the lists most).
static size_t grown_capacity(size_t cap) {
  constexpr size_t kDoubleUpTo = size_t(1) << 16;
  return cap < kDoubleUpTo ? 2 * cap : (cap + cap / 4 + 7) / 8 * 8;
}

void StepKernels::reserve(size_t want) {
  const size_t capacity = s.particles.capacity();
  if (want <= capacity) return;
  size_t cap = std::max<size_t>(capacity, 64);
  while (cap < want) cap = grown_capacity(cap);
  if (cap > max_particles())
    throw Error("engine: " + std::to_string(want) + " particles are more than the " + form_name() + " form holds (" +
                std::to_string(max_particles()) + "); use a larger radius");
  s.records->finish_pending(s.steps);  // the record buffers are reallocated below
  s.particles.grow(cap, copies());
  s.lists.reserve(cap, reserve_form(cap));
  s.cells.reserve(cap);
  for (Kernel* k : kernels()) k->forget_args();  // new buffers may reuse a freed buffer's handle
  s.records->reserve(level1_count(cap), s.steps);
}

void StepKernels::set_domain(const Box3& box, const ScalarGrid* field) {
  s.cells.set_domain(box, field);
  s.lists.valid = false;
  for (Kernel* k : kernels()) k->forget_args();
}

void StepKernels::birth(size_t index, const cl_float4& x, const cl_float4& v) {
  bind_shared(birth_one, false);
  birth_one.set("index", cl_uint(index)).set("x", x).set("v", v);
  s.run(birth_one, 1);
}

void StepKernels::birth_linked(const cl_float4& x, const cl_float4& v) {
  bind_shared(link_birth, false);
  link_birth.set("x", x).set("v", v);
  s.run(link_birth, s.n + 1);
}

void StepKernels::remove_linked(size_t gone) {
  bind_shared(unlink_removal, false);
  unlink_removal.set("gone", cl_uint(gone));
  s.run(unlink_removal, s.n);
}

void StepKernels::move(size_t from, size_t to) {
  bind_shared(move_particle, false);
  move_particle.set("from", cl_uint(from)).set("to", cl_uint(to));
  s.run(move_particle, 1);
}

std::vector<std::vector<uint32_t>> StepKernels::neighbour_lists() {
  s.cells.require_domain();
  insert_cells(true);
  const size_t n = s.n;
  // (a large sphere among small ones has about as many as the lists hold)
  const cl_uint max_out = std::max<cl_uint>(256, s.constants.list_capacity);
  DeviceArray<cl_uint> counts(s.device, "neighbour counts"), lists(s.device, "neighbour lists");
  counts.reset(n);
  lists.reset(n * max_out);
  bind_shared(list_neighbours, false);
  list_neighbours.set("out_count", counts).set("out", lists).set("max_out", max_out);
  s.run(list_neighbours, n);
  s.cells.clear();  // as the steps expect them: this step's set empty
  const std::vector<cl_uint> c = counts.read(n), l = lists.read(n * max_out);
  std::vector<std::vector<uint32_t>> out(n);
  for (size_t i = 0; i < n; ++i) {
    if (c[i] > max_out)
      throw Error("engine: particle " + std::to_string(i) + " has more than " + std::to_string(max_out) + " neighbours");
    out[i].assign(l.begin() + i * max_out, l.begin() + i * max_out + c[i]);
  }
  return out;
}

}  // namespace pfill

namespace pfill {

std::unique_ptr<StepKernels> make_cpu_step(EngineState& s);  // cpu_step.cpp
std::unique_ptr<StepKernels> make_gpu_step(EngineState& s);  // gpu_step.cpp

std::unique_ptr<StepKernels> StepKernels::make(EngineState& s) {
  return s.choices.gpu_form ? make_gpu_step(s) : make_cpu_step(s);
}

}  // namespace pfill
