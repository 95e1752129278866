// The OpenCL particle engine as a facade over its parts (engine_state.hpp):
// the particles' arrays, the neighbour lists, the cells, the wall, the
// step history, and the step form's kernels (step_kernels.hpp).
#include "pfill/engine/engine.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>
#include <vector>

#include "engine/engine_state.hpp"
#include "engine/step_kernels.hpp"
#include "pfill/device/device.hpp"
#include "pfill/error.hpp"

namespace pfill {

namespace {

cl_float4 f4(double x, double y, double z, double w) {
  cl_float4 v;
  v.s[0] = static_cast<float>(x);
  v.s[1] = static_cast<float>(y);
  v.s[2] = static_cast<float>(z);
  v.s[3] = static_cast<float>(w);
  return v;
}

// The bit of the cell level a sphere of radius r falls in (cells.cl
// pf_level_of, in floats as the kernels compare), and its neighbours' (so
// that a rounding on the way cannot leave its level out).
cl_uint cell_level_bits(const EngineConstants& c, double r) {
  const float r0 = static_cast<float>(c.level_radius * (1 + 1e-6)), rf = static_cast<float>(r);
  unsigned level = 0;
  while (level + 1 < c.cell_levels && rf > r0 * static_cast<float>(1u << level)) ++level;
  return (7u << level) >> 1;
}

// Most removals at once that edit the lists in place (remove_linked: a
// launch over every particle's row each); more go cheaper as a rebuild at
// the next step, which costs about 10-14 edits (spot, PoCL: 0.95 ms an edit
// and 9 ms a rebuild at 1e5; at 1e6 the finish's 4,086 deletions spent 27 s
// editing, 6.5 ms each).
constexpr size_t kMostLinkedRemovals = 8;

}  // namespace

struct Engine::Impl {
  EngineState state;
  std::unique_ptr<StepKernels> form;
  std::vector<cl_float4> view_positions;  // birth_view's read, kept for the next

  Impl(Device& device, const EngineParams& params) : state(device, params), form(StepKernels::make(state)) {
    form->reserve(64);
    if (!state.params.domain.empty()) form->set_domain(state.params.domain);
  }
};

Engine::Engine(Device& device, const EngineParams& params) : impl_(std::make_unique<Impl>(device, params)) {
  restart_minimiser();
}
Engine::~Engine() = default;

const EngineParams& Engine::params() const { return impl_->state.params; }
const EngineConstants& Engine::constants() const { return impl_->state.constants; }
const DeviceChoices& Engine::choices() const { return impl_->state.choices; }
std::string Engine::describe() const { return impl_->state.choices.describe(); }
size_t Engine::size() const { return impl_->state.n + impl_->state.hold.out; }
uint64_t Engine::steps_done() const { return impl_->state.steps; }

void Engine::set_field(const ScalarGrid& field) { set_field(field, false); }

void Engine::share_field(const ScalarGrid& field) { set_field(field, true); }

void Engine::set_field(const ScalarGrid& field, bool borrow) {
  impl_->state.wall.set(field, borrow);
  impl_->state.particles.forget_kept_cells();  // the kept corners are the old field's
  Box3 box;
  box.add(field.origin);
  box.add(field.upper());
  impl_->form->set_domain(box, &field);
}

size_t Engine::add_particles(const std::vector<Particle>& particles) {
  release_hold();  // (after the others)
  EngineState& s = impl_->state;
  const size_t first = s.n;
  if (particles.empty()) return first;
  std::vector<cl_float4> xs, vs;
  for (const Particle& p : particles) {
    if (!(p.radius > 0 && p.radius <= s.constants.max_radius * (1 + 1e-9)))
      throw Error("engine: particle radius " + std::to_string(p.radius) + " is outside (0, max_radius = " +
                  std::to_string(s.constants.max_radius) + "]; raise EngineParams::max_radius");
    if (!is_finite(p.position) || !is_finite(p.velocity) || p.mass < 0 || !std::isfinite(p.mass))
      throw Error("engine: a particle to add has a non-finite position or velocity, or a bad mass");
    const double mass = p.mass > 0 ? p.mass : particle_mass(s.params, p.radius);
    xs.push_back(f4(p.position.x, p.position.y, p.position.z, p.radius));
    vs.push_back(f4(p.velocity.x, p.velocity.y, p.velocity.z, 1 / mass));
  }
  for (const Particle& p : particles) s.level_mask |= cell_level_bits(s.constants, p.radius);
  impl_->form->reserve(first + particles.size());
  for (const Particle& p : particles) s.particles.ids.push_back(p.id);
  if (particles.size() == 1 && s.lists.valid && s.lists.newcomers.size() < 4) {  // linked into the lists in place
    impl_->form->birth_linked(xs[0], vs[0]);
    s.lists.newcomers.push_back(static_cast<int>(first));
  } else if (particles.size() == 1) {
    s.lists.valid = false;  // the next step lists the newcomer
    impl_->form->birth(first, xs[0], vs[0]);
  } else {
    s.lists.valid = false;
    s.particles.write(first, xs, vs);
  }
  s.n += particles.size();
  return first;
}

void Engine::remove_particles(std::vector<size_t> indices) {
  release_hold();  // (a swap with the last of all)
  EngineState& s = impl_->state;
  std::sort(indices.begin(), indices.end(), std::greater<size_t>());
  indices.erase(std::unique(indices.begin(), indices.end()), indices.end());
  for (size_t idx : indices)
    if (idx >= s.n) throw Error("engine: cannot remove particle " + std::to_string(idx) + " of " + std::to_string(s.n));
  std::vector<uint64_t>& ids = s.particles.ids;
  if (indices.size() > kMostLinkedRemovals) s.lists.valid = false;  // (each then a swap with the last)
  for (size_t idx : indices) {
    const size_t last = s.n - 1;
    if (s.lists.valid) {  // keep the lists: drop `idx`, rename `last`
      impl_->form->remove_linked(idx);
      // A newcomer's unsorted row moves with it from `last` to `idx`.
      for (int& k : s.lists.newcomers)
        if (k == static_cast<int>(idx)) k = -1;
      for (int& k : s.lists.newcomers)
        if (k == static_cast<int>(last)) k = static_cast<int>(idx);
    } else if (idx != last) {
      impl_->form->move(last, idx);
    }
    ids[idx] = ids[last];  // the ids follow the swap with the last
    ids.pop_back();
    s.lists.clear_count(last);  // counts past the last particle stay 0 (a linked birth counts up from there)
    s.n -= 1;
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
  for (size_t s = 0; s < k; ++s) impl_->form->step();
}

void Engine::restart_minimiser() {
  EngineState& s = impl_->state;
  if (!s.params.fire.on) return;
  s.records->finish_pending(s.steps);  // the records in flight would write the state after this
  cl_float8 v{};
  v.s[0] = static_cast<float>(s.constants.dt);
  v.s[1] = static_cast<float>(s.params.fire.alpha_start);
  const cl_uint restart_step = static_cast<cl_uint>(s.steps);  // (common.cl pf_fire_save: as uint bits)
  std::memcpy(&v.s[5], &restart_step, sizeof restart_step);
  s.fire.write(s.steps % 2, {v});
}

Engine::MinimiserState Engine::minimiser_state() {
  EngineState& s = impl_->state;
  if (!s.params.fire.on) return {};
  s.records->finish_pending(s.steps);
  std::vector<cl_float8> v;
  s.fire.read(2, v);
  const cl_float8& now = v[s.steps % 2];
  MinimiserState m;
  m.dt = now.s[0];
  m.alpha = now.s[1];
  m.restarts = now.s[4];
  return m;
}

std::vector<StepRecord> Engine::read_history() {
  impl_->state.records->drain(impl_->state.steps);
  return impl_->state.records->take();
}

std::vector<Particle> Engine::read_particles() {
  const EngineState& s = impl_->state;
  const size_t count = size();
  std::vector<cl_float4> xs, vs;
  s.particles.read(count, xs, vs);
  std::vector<Particle> out(count);
  for (size_t i = 0; i < count; ++i) {
    out[i].position = {xs[i].s[0], xs[i].s[1], xs[i].s[2]};
    out[i].radius = xs[i].s[3];
    out[i].velocity = {vs[i].s[0], vs[i].s[1], vs[i].s[2]};
    out[i].mass = 1.0 / (i < s.n && s.hold.active ? s.hold.inverse_mass[i] : vs[i].s[3]);
    out[i].id = s.particles.ids[i];
  }
  return out;
}

BirthView Engine::birth_view(double, bool) {
  const size_t count = size();
  std::vector<cl_float4>& xs = impl_->view_positions;
  impl_->state.particles.x().read(count, xs);
  BirthView view;
  view.centres.resize(count);
  view.radii.resize(count);
  for (size_t i = 0; i < count; ++i) {
    view.centres[i] = {xs[i].s[0], xs[i].s[1], xs[i].s[2]};
    view.radii[i] = xs[i].s[3];
  }
  view.own = count;
  return view;
}

std::vector<size_t> Engine::sort_by_cells() {
  EngineState& s = impl_->state;
  s.cells.require_domain();
  s.records->finish_pending(s.steps);
  std::vector<cl_float4> xs, vs;
  s.particles.read(s.n, xs, vs);
  std::vector<std::pair<uint64_t, size_t>> keyed(s.n);
  for (size_t i = 0; i < s.n; ++i) keyed[i] = {s.cells.morton_key(xs[i]), i};
  std::sort(keyed.begin(), keyed.end());  // (key, old index): ties keep their order
  std::vector<size_t> order(s.n);
  for (size_t k = 0; k < s.n; ++k) order[k] = keyed[k].second;
  s.particles.permute(order, std::move(xs), std::move(vs));  // (in a hold: those taking part, among themselves)
  if (s.hold.active) {
    std::vector<cl_float> own(s.n);
    for (size_t k = 0; k < s.n; ++k) own[k] = s.hold.inverse_mass[order[k]];
    s.hold.inverse_mass = std::move(own);
    for (size_t k = s.n; k < size(); ++k) order.push_back(k);
  }
  s.lists.valid = false;  // the next step rebuilds every list
  s.lists.newcomers.clear();
  return order;
}

std::optional<size_t> Engine::hold(const std::function<StepPart(const Vec3&)>& part_of) {
  release_hold();
  return hold_particles(impl_->state, part_of);
}

void Engine::release_hold() { release_particles(impl_->state); }

std::vector<size_t> Engine::flagged_particles() { return impl_->state.particles.flagged(impl_->state.n); }

void Engine::clear_flags() { impl_->state.particles.flags.zero(); }

void Engine::finish() { impl_->state.device.finish(); }

std::vector<std::vector<uint32_t>> Engine::neighbour_lists() { return impl_->form->neighbour_lists(); }

std::vector<std::vector<uint32_t>> Engine::step_lists() {
  const EngineState& s = impl_->state;
  if (!s.lists.valid) return std::vector<std::vector<uint32_t>>(s.n);
  return s.lists.read(s.n);
}

std::map<std::string, double> Engine::kernel_times() {
  EngineState& s = impl_->state;
  std::map<std::string, double> out;
  if (!s.device.profiling()) return out;
  s.device.finish();
  for (auto& [name, ev] : s.events) {
    cl_ulong start = 0, end = 0;
    check_cl(ev.getProfilingInfo(CL_PROFILING_COMMAND_START, &start), "clGetEventProfilingInfo", name);
    check_cl(ev.getProfilingInfo(CL_PROFILING_COMMAND_END, &end), "clGetEventProfilingInfo", name);
    out[name] += static_cast<double>(end - start) * 1e-9;
  }
  s.events.clear();
  return out;
}

}  // namespace pfill
