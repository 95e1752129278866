// FIRE on the LAMMPS engine: see fire_minimiser.hpp.
#ifdef PFILL_WITH_LAMMPS
#include "lammps/fire_minimiser.hpp"

#include "../../kernels/physics_double.hpp"

namespace pfill {
namespace lammps_engine {

FireMinimiser::FireMinimiser(const EngineParams& params, const EngineConstants& constants,
                             const LammpsSession& session)
    : on_(params.fire.on), rule_(params.fire), first_dt_(constants.dt), session_(session) {
  restart(0);
}

double FireMinimiser::end_step(uint64_t step, double mine) {
  if (!on_) return 0;
  double power = mine;
  if (session_.ranks() > 1) {
    // Allgather, not Allreduce: each rank sums the same shares in the same
    // order, so P, and every decision on its sign, is the same bits on each.
    powers_.assign(static_cast<size_t>(session_.ranks()), 0.0);
    MPI_Allgather(&mine, 1, MPI_DOUBLE, powers_.data(), 1, MPI_DOUBLE, session_.comm());
    power = 0;
    for (double p : powers_) power += p;
  }
  // As the OpenCL engine's step t: it takes in the record of step t - 2 when that is in flight.
  if (!in_flight_.empty() && in_flight_.front().first + 2 == step) {
    take_in(in_flight_.front().first, in_flight_.front().second, step + 1);
    in_flight_.erase(in_flight_.begin());
  }
  in_flight_.emplace_back(step, power);
  return power;
}

void FireMinimiser::take_in_flight(uint64_t steps_done) {
  if (!on_) return;
  for (const auto& [step, power] : in_flight_) take_in(step, power, steps_done);
  in_flight_.clear();
}

void FireMinimiser::restart(uint64_t steps_done) {
  if (!on_) return;
  take_in_flight(steps_done);
  dt_ = first_dt_, alpha_ = rule_.alpha_start, backtrack_ = 0, positive_ = 0, restarts_ = 0;
  restart_step_ = static_cast<uint32_t>(steps_done);
}

ParticleEngine::MinimiserState FireMinimiser::state() const {
  ParticleEngine::MinimiserState m;
  if (on_) m.dt = dt_, m.alpha = alpha_, m.restarts = restarts_;
  return m;
}

void FireMinimiser::take_in(uint64_t record_step, double power, uint64_t effect_step) {
  physics::pf_fire_rule r;
  r.dt_max = rule_.dt_max * first_dt_;
  r.dt_min = rule_.dt_min * first_dt_;
  r.grow = rule_.grow;
  r.shrink = rule_.shrink;
  r.alpha_start = rule_.alpha_start;
  r.alpha_shrink = rule_.alpha_shrink;
  r.delay = rule_.delay;
  physics::pf_fire_state s{dt_, alpha_, backtrack_, positive_, restarts_, restart_step_};
  s = physics::pf_fire_next(s, r, power, static_cast<uint32_t>(record_step), static_cast<uint32_t>(effect_step));
  dt_ = s.dt, alpha_ = s.alpha, backtrack_ = s.backtrack, positive_ = s.positive, restarts_ = s.restarts;
  restart_step_ = s.restart_step;
}

}  // namespace lammps_engine
}  // namespace pfill
#endif
