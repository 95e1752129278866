// The OpenCL engine's hold (engine_hold.hpp).
#include "engine/engine_hold.hpp"

#include <utility>

#include "engine/engine_state.hpp"

namespace pfill {

size_t hold_particles(EngineState& s, const std::function<ParticleEngine::StepPart(const Vec3&)>& part_of) {
  using Part = ParticleEngine::StepPart;
  s.records->finish_pending(s.steps);
  std::vector<cl_float4> xs, vs;
  s.particles.read(s.n, xs, vs);
  std::vector<size_t> order, out;
  std::vector<cl_float> own;
  order.reserve(s.n);
  for (size_t i = 0; i < s.n; ++i) {
    const Part part = part_of(Vec3{xs[i].s[0], xs[i].s[1], xs[i].s[2]});
    if (part == Part::out) {
      out.push_back(i);
      continue;
    }
    order.push_back(i);
    own.push_back(vs[i].s[3]);
    if (part == Part::held) vs[i] = cl_float4{{0.0f, 0.0f, 0.0f, kHeldInverseMass}};  // (at rest: a speed moves it)
  }
  const size_t taking = order.size();
  order.insert(order.end(), out.begin(), out.end());
  s.particles.permute(order, std::move(xs), std::move(vs));
  s.hold.active = true;
  s.hold.out = out.size();
  s.hold.inverse_mass = std::move(own);
  s.n = taking;
  s.lists.valid = false;  // the next step lists the ones taking part
  s.lists.newcomers.clear();
  return taking;
}

void release_particles(EngineState& s) {
  if (!s.hold.active) return;
  s.records->finish_pending(s.steps);
  std::vector<cl_float4> xs, vs;
  s.particles.read(s.n, xs, vs);
  for (size_t k = 0; k < s.n; ++k) vs[k].s[3] = s.hold.inverse_mass[k];
  s.particles.write_velocities(0, vs);
  s.n += s.hold.out;
  s.hold = HoldState{};
  s.lists.valid = false;  // the next step lists them all
  s.lists.newcomers.clear();
}

}  // namespace pfill
